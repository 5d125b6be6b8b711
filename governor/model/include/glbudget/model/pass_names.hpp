#pragma once
// The names behind PassIndex (power_model.hpp) where names come in: a frame log's pass hashes,
// a variant table's or manifest's pass names. The space's passes come first, each at its
// index in the space; any other name gets the next index the first time it is seen. The
// model itself never compares names.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/power_model.hpp"

namespace glbudget::model {

class PassNames {
 public:
  PassNames() = default;
  explicit PassNames(const ConfigurationSpace& space);

  // The name's index, given a new one if it has none yet.
  PassIndex index_of(std::string_view name);
  std::optional<PassIndex> find(std::string_view name) const;
  // "" for an index never given.
  const std::string& name(PassIndex pass) const;
  std::size_t size() const { return names_.size(); }

 private:
  std::vector<std::string> names_;
  std::map<std::string, PassIndex, std::less<>> index_;
};

}  // namespace glbudget::model
