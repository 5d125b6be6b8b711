// Hall: ~230k triangles, 23 objects; one spot light, a reflective floor and two metallic
// statues (paper, Table 3).
#include <cmath>

#include "scenes/registry.hpp"
#include "scenes/scene_kit.hpp"

namespace demo {

Scene make_hall(float detail) {
  using namespace kit;
  const auto n = [detail](int triangles) { return scaled(triangles, detail); };
  Scene s;
  s.name = "hall";
  s.add("floor", plane(30.0f, 20.0f, n(20000)), reflective(0.25f, 0.22f, 0.2f, 0.15f, 0.6f));
  s.add("ceiling", plane(30.0f, 20.0f, n(4000)), matte(0.8f, 0.78f, 0.72f),
        Eigen::Translation3f(0.0f, 8.0f, 0.0f) * Eigen::AngleAxisf(3.14159265f, Eigen::Vector3f::UnitX()));
  s.add("wall_north", box({15.0f, 4.0f, 0.2f}, n(3000)), matte(0.7f, 0.6f, 0.5f), at(0.0f, 4.0f, -10.0f));
  s.add("wall_south", box({15.0f, 4.0f, 0.2f}, n(3000)), matte(0.7f, 0.6f, 0.5f), at(0.0f, 4.0f, 10.0f));
  s.add("wall_west", box({0.2f, 4.0f, 10.0f}, n(3000)), matte(0.6f, 0.55f, 0.5f), at(-15.0f, 4.0f, 0.0f));
  s.add("wall_east", box({0.2f, 4.0f, 10.0f}, n(3000)), matte(0.6f, 0.55f, 0.5f), at(15.0f, 4.0f, 0.0f));
  for (int i = 0; i < 12; ++i) {
    const float x = -12.5f + (i % 6) * 5.0f, z = i < 6 ? -6.0f : 6.0f;
    s.add("column", cylinder(0.5f, 0.45f, 8.0f, n(6000)), matte(0.85f, 0.82f, 0.75f, 0.5f), at(x, 0.0f, z));
  }
  for (int i = 0; i < 2; ++i) {
    const float x = i ? 4.0f : -4.0f;
    s.add("pedestal", box({0.8f, 0.5f, 0.8f}, n(1000)), matte(0.3f, 0.3f, 0.32f, 0.4f), at(x, 0.5f, 0.0f));
    const Material m = i ? metal(0.95f, 0.64f, 0.54f, 0.25f) : metal(0.91f, 0.92f, 0.92f, 0.15f);
    s.add("statue", torus_knot(i ? 3 : 2, i ? 2 : 3, 1.4f, 0.3f, n(55000)), m, at(x, 2.3f, 0.0f, 0.3f));
  }
  s.add("chandelier", torus(1.2f, 0.08f, n(6000)), metal(0.9f, 0.8f, 0.5f, 0.3f), at(0.0f, 7.2f, 0.0f));

  Light spot;
  spot.type = Light::Type::Spot;
  spot.position = {0.0f, 7.6f, 1.0f};
  spot.direction = Eigen::Vector3f(0.0f, -1.0f, -0.15f).normalized();
  spot.color = {260.0f, 240.0f, 210.0f};
  spot.cone_deg = 60.0f;
  s.lights.push_back(spot);
  s.sky = {0.12f, 0.12f, 0.14f};
  s.ground = {0.06f, 0.05f, 0.05f};
  s.shadow_centre = {0.0f, 2.0f, 0.0f};
  s.shadow_radius = 16.0f;
  s.far_plane = 60.0f;
  s.reflection_distance = 12.0f;
  s.camera = [](double t) {
    const auto a = static_cast<float>(0.25 * t);
    return CameraPose{{11.0f * std::cos(a), 2.2f, 7.5f * std::sin(a)}, {0.0f, 2.0f, 0.0f}, 60.0f};
  };
  return s;
}

}  // namespace demo
