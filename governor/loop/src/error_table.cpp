#include "glbudget/loop/error_table.hpp"

#include <cmath>
#include <limits>

namespace glbudget::loop {

ErrorTable::ErrorTable(const model::ConfigurationSpace& space) {
  for (const model::PassVariants& variants : space.passes()) {
    Pass pass{variants.pass, {}, {}};
    const std::size_t levels = variants.levels.size();
    for (std::size_t l = 0; l < levels; ++l) {
      pass.error.push_back(stand_in(static_cast<int>(l), levels));
      pass.stand_in.push_back(l > 0);  // level 0 is exact: the reference
    }
    passes_.push_back(std::move(pass));
  }
}

double ErrorTable::stand_in(int level, std::size_t levels) {
  if (level <= 0 || levels < 2) return 0.0;
  return 0.01 * static_cast<double>(level) / static_cast<double>(levels - 1);
}

bool ErrorTable::set(std::size_t pass, int level, double error) {
  if (pass >= passes_.size() || level <= 0 || static_cast<std::size_t>(level) >= passes_[pass].error.size() ||
      !std::isfinite(error) || error < 0.0) {
    return false;
  }
  passes_[pass].error[static_cast<std::size_t>(level)] = error;
  passes_[pass].stand_in[static_cast<std::size_t>(level)] = false;
  return true;
}

double ErrorTable::error(std::size_t pass, int level) const {
  if (pass >= passes_.size() || level < 0 || static_cast<std::size_t>(level) >= passes_[pass].error.size()) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return passes_[pass].error[static_cast<std::size_t>(level)];
}

bool ErrorTable::is_stand_in(std::size_t pass, int level) const {
  return pass < passes_.size() && level >= 0 && static_cast<std::size_t>(level) < passes_[pass].stand_in.size() &&
         passes_[pass].stand_in[static_cast<std::size_t>(level)];
}

std::vector<std::string> ErrorTable::stand_in_passes() const {
  std::vector<std::string> names;
  for (const Pass& pass : passes_) {
    for (bool stand_in : pass.stand_in) {
      if (stand_in) {
        names.push_back(pass.name);
        break;
      }
    }
  }
  return names;
}

bool ErrorTable::fits(const model::ConfigurationSpace& space) const {
  if (space.pass_count() != passes_.size()) return false;
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    const model::PassVariants& variants = space.passes()[i];
    if (variants.pass != passes_[i].name || variants.levels.size() != passes_[i].error.size()) return false;
  }
  return true;
}

double ErrorTable::estimate(const model::Configuration& configuration) const {
  if (configuration.size() != passes_.size()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (std::size_t i = 0; i < passes_.size(); ++i) sum += error(i, configuration[i]);
  return sum;
}

std::size_t ErrorTable::size() const {
  std::size_t n = 1;
  for (const Pass& pass : passes_) n *= pass.error.size();
  return n;
}

// Built in place one pass at a time: after pass i, out[0, n) holds the sums over passes
// [0, i] in row-major order, and entry j expands into [j L, (j + 1) L). Going backwards, no
// entry is overwritten before it has been read (j L + l >= j, equal only for j = 0, l = 0).
void ErrorTable::estimate_all(std::vector<double>& out) const {
  out.resize(size());
  out[0] = 0.0;
  std::size_t n = 1;
  for (const Pass& pass : passes_) {
    const std::size_t levels = pass.error.size();
    for (std::size_t j = n; j-- > 0;) {
      const double base = out[j];
      for (std::size_t l = levels; l-- > 0;) out[j * levels + l] = base + pass.error[l];
    }
    n *= levels;
  }
}

}  // namespace glbudget::loop
