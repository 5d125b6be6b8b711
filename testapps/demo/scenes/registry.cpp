#include "scenes/registry.hpp"

namespace demo {

const std::vector<std::string_view>& scene_names() {
  static const std::vector<std::string_view> names{"hall", "sponza", "valley", "subway"};
  return names;
}

bool is_scene_name(std::string_view name) {
  for (std::string_view known : scene_names()) {
    if (known == name) return true;
  }
  return false;
}

std::optional<Scene> make_scene(std::string_view name, float detail) {
  if (name == "hall") return make_hall(detail);
  if (name == "sponza") return make_sponza(detail);
  if (name == "valley") return make_valley(detail);
  if (name == "subway") return make_subway(detail);
  return std::nullopt;
}

}  // namespace demo
