#include "glbudget/model/pass_names.hpp"

namespace glbudget::model {

PassNames::PassNames(const ConfigurationSpace& space) {
  for (const PassVariants& pass : space.passes()) {
    // A name the space repeats keeps its first index; the later pass is reached by index only.
    index_.try_emplace(pass.pass, static_cast<PassIndex>(names_.size()));
    names_.push_back(pass.pass);
  }
}

PassIndex PassNames::index_of(std::string_view name) {
  if (const auto it = index_.find(name); it != index_.end()) return it->second;
  const auto index = static_cast<PassIndex>(names_.size());
  names_.emplace_back(name);
  index_.emplace(std::string(name), index);
  return index;
}

std::optional<PassIndex> PassNames::find(std::string_view name) const {
  if (const auto it = index_.find(name); it != index_.end()) return it->second;
  return std::nullopt;
}

const std::string& PassNames::name(PassIndex pass) const {
  static const std::string none;
  return pass < names_.size() ? names_[pass] : none;
}

}  // namespace glbudget::model
