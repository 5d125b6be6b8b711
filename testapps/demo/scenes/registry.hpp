// The four scenes of the paper's Table 3, built procedurally at a --detail scale
// (1 = the paper's triangle counts; object counts do not change with detail).
#pragma once
#include <optional>
#include <string_view>
#include <vector>

#include "scene.hpp"

namespace demo {

Scene make_hall(float detail);
Scene make_sponza(float detail);
Scene make_valley(float detail);
Scene make_subway(float detail);

const std::vector<std::string_view>& scene_names();  // hall, sponza, valley, subway
bool is_scene_name(std::string_view name);
std::optional<Scene> make_scene(std::string_view name, float detail);

}  // namespace demo
