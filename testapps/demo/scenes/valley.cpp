// Valley: ~140k triangles, 61 objects; terrain under the sun, nothing reflective or metallic
// (paper, Table 3).
#include <cmath>

#include "scenes/registry.hpp"
#include "scenes/scene_kit.hpp"

namespace demo {
namespace {
// A valley along z: flat floor, hills rising with |x|, ripples everywhere.
float valley_height(float x, float z) {
  const float walls = 0.004f * x * x * std::abs(x) / 10.0f;
  return walls + 1.2f * std::sin(0.13f * x + 0.4f) * std::cos(0.11f * z) + 0.4f * std::sin(0.5f * z + 0.3f * x);
}
}  // namespace

Scene make_valley(float detail) {
  using namespace kit;
  const auto n = [detail](int triangles) { return scaled(triangles, detail); };
  Scene s;
  s.name = "valley";
  s.add("terrain", terrain(120.0f, n(82000), valley_height), matte(0.32f, 0.45f, 0.2f, 0.9f));
  Rng rng(61);
  for (int i = 0; i < 40; ++i) {
    const float x = rng.uniform(-22.0f, 22.0f), z = rng.uniform(-50.0f, 40.0f);
    const float size = rng.uniform(0.7f, 1.4f);
    Mesh tree = cylinder(0.25f, 0.18f, 2.0f, n(300));
    tree.append(cylinder(1.6f, 0.0f, 4.5f, n(900)), at(0.0f, 1.5f, 0.0f));
    s.add("tree", tree, matte(0.18f, 0.35f, 0.12f, 0.8f), at(x, valley_height(x, z) - 0.1f, z, 0.0f, size));
  }
  for (int i = 0; i < 20; ++i) {
    const float x = rng.uniform(-30.0f, 30.0f), z = rng.uniform(-50.0f, 40.0f);
    s.add("rock", sphere(1.0f, n(700)), matte(0.45f, 0.43f, 0.4f, 0.8f),
          at(x, valley_height(x, z), z, rng.uniform(0.0f, 6.0f), rng.uniform(0.5f, 1.8f)));
  }

  Light sun;
  sun.type = Light::Type::Directional;
  sun.direction = Eigen::Vector3f(-0.5f, -0.8f, -0.35f).normalized();
  sun.color = {3.0f, 2.85f, 2.6f};
  s.lights.push_back(sun);
  s.sky = {0.45f, 0.6f, 0.85f};
  s.ground = {0.2f, 0.22f, 0.12f};
  s.shadow_centre = {0.0f, 3.0f, 0.0f};
  s.shadow_radius = 55.0f;
  s.far_plane = 200.0f;
  s.camera = [](double t) {  // flies down the valley and back, 2 units/s
    const double along = std::fmod(2.0 * t, 140.0);
    const auto z = static_cast<float>(35.0 - (along < 70.0 ? along : 140.0 - along));
    return CameraPose{{3.0f * std::sin(0.3f * z), 6.0f, z}, {0.0f, 2.0f, z - 20.0f}, 60.0f};
  };
  return s;
}

}  // namespace demo
