#pragma once
// Quality-error estimates for every configuration by the additivity of paper §6.2:
//   e(s) ~ sum_i e_i(l_i),
// where e_i(l) is the error (1 - SSIM against the best configuration s0) of the configuration
// with every pass at its best but pass i at level l, and e_i(0) = 0.
//
// Until quality probes measure e_i(l), the values come from the manifest's `error` keys; a
// level without one gets the stand-in e_i(l) = 0.01 l / (levels_i - 1): cheaper levels are
// taken to be worse, every pass weighs the same, and the whole scene at its worst costs 0.01
// per pass. The table remembers which levels are stand-ins, so the governor can say so.
#include <cstddef>
#include <string>
#include <vector>

#include "glbudget/model/configuration_space.hpp"

namespace glbudget::loop {

class ErrorTable {
 public:
  ErrorTable() = default;
  // The space's passes (names and level counts), every level at the stand-in.
  explicit ErrorTable(const model::ConfigurationSpace& space);

  // 0.01 l / (levels - 1); 0 for level 0 or a single level.
  static double stand_in(int level, std::size_t levels);

  // Sets e_i(l), measured or given. False, and nothing changes, for a pass or level outside
  // the table, for level 0 (the reference: its error is 0) and for a value that is not
  // finite or is negative.
  bool set(std::size_t pass, int level, double error);

  std::size_t pass_count() const { return passes_.size(); }
  std::size_t level_count(std::size_t pass) const { return passes_[pass].error.size(); }
  const std::string& pass_name(std::size_t pass) const { return passes_[pass].name; }
  double error(std::size_t pass, int level) const;
  bool is_stand_in(std::size_t pass, int level) const;
  // Names of the passes with at least one level at the stand-in, in order.
  std::vector<std::string> stand_in_passes() const;
  // The same passes, by name and level count, in the same order as the space.
  bool fits(const model::ConfigurationSpace& space) const;

  // NaN for a configuration of another length or with a level outside the table.
  double estimate(const model::Configuration& configuration) const;
  // out[space.index_of(c)] = estimate(c), for the space this table fits (row-major, last
  // pass fastest). Allocates nothing once `out` has the size.
  void estimate_all(std::vector<double>& out) const;
  std::size_t size() const;  // configurations

 private:
  struct Pass {
    std::string name;
    std::vector<double> error;   // [level]
    std::vector<bool> stand_in;  // [level]
  };
  std::vector<Pass> passes_;
};

}  // namespace glbudget::loop
