// Subway: ~525k triangles, ~450 objects; one bulb spot light, a reflective floor and two
// animated, skinned metallic soldiers: the dynamic scene (paper, Table 3).
#include <cmath>

#include "scenes/registry.hpp"
#include "scenes/scene_kit.hpp"

namespace demo {
namespace {
// The soldiers march 20 units along +x and back (0.8 units/s), turning at the ends.
constexpr double kMarchLength = 20.0, kMarchSpeed = 0.8;
double march_cycle(double t) { return std::fmod(kMarchSpeed * t, 2.0 * kMarchLength); }
float march_x(double t) {
  const double c = march_cycle(t);
  return static_cast<float>(c < kMarchLength ? c - 10.0 : 10.0 - (c - kMarchLength));
}
// Model +z faces the direction of the march.
float march_heading(double t) { return march_cycle(t) < kMarchLength ? 1.5708f : -1.5708f; }
}  // namespace

Scene make_subway(float detail) {
  using namespace kit;
  const auto n = [detail](int triangles) { return scaled(triangles, detail); };
  Scene s;
  s.name = "subway";
  const Material tile = matte(0.75f, 0.75f, 0.7f, 0.4f);
  s.add("platform", plane(60.0f, 10.0f, n(30000)), reflective(0.35f, 0.33f, 0.3f, 0.2f, 0.45f), at(0.0f, 0.0f, -1.0f));
  s.add("track_bed", plane(60.0f, 5.0f, n(4000)), matte(0.2f, 0.18f, 0.16f, 0.9f), at(0.0f, -1.2f, 6.5f));
  s.add("wall", box({30.0f, 3.0f, 0.3f}, n(4000)), tile, at(0.0f, 2.0f, -6.3f));
  s.add("wall", box({30.0f, 3.0f, 0.3f}, n(4000)), tile, at(0.0f, 2.0f, 9.3f));
  s.add("ceiling", box({30.0f, 0.3f, 8.0f}, n(4000)), matte(0.5f, 0.5f, 0.52f), at(0.0f, 5.2f, 1.5f));
  for (int i = 0; i < 30; ++i) {
    const float x = -29.0f + (i % 15) * 4.0f, z = i < 15 ? -3.5f : 3.5f;
    s.add("pillar", cylinder(0.3f, 0.3f, 5.0f, n(6000)), matte(0.55f, 0.2f, 0.15f, 0.5f), at(x, 0.0f, z));
  }
  for (int i = 0; i < 4; ++i) {
    s.add("rail", box({30.0f, 0.08f, 0.05f}, n(200)), metal(0.6f, 0.6f, 0.62f, 0.35f),
          at(0.0f, -1.05f, 5.5f + (i % 2) * 1.4f + (i / 2) * 2.2f));
  }
  for (int i = 0; i < 120; ++i) {
    s.add("sleeper", box({0.12f, 0.06f, 1.9f}, 12), matte(0.3f, 0.22f, 0.15f), at(-29.75f + i * 0.5f, -1.14f, 6.5f));
  }
  for (int i = 0; i < 20; ++i) {
    s.add("bench", box({0.9f, 0.25f, 0.3f}, n(500)), matte(0.25f, 0.3f, 0.45f), at(-28.0f + i * 3.0f, 0.45f, -5.4f));
  }
  Rng rng(453);
  for (int i = 0; i < 200; ++i) {  // tiled wall panels and posters
    const float x = -29.5f + (i % 100) * 0.6f, y = i < 100 ? 1.2f : 3.2f;
    s.add("panel", box({0.28f, 0.9f, 0.04f}, n(300)),
          matte(rng.uniform(0.3f, 0.9f), rng.uniform(0.3f, 0.9f), rng.uniform(0.3f, 0.9f), 0.3f), at(x, y, -5.95f));
  }
  for (int i = 0; i < 30; ++i) {
    s.add("lamp", sphere(0.18f, n(1500)), matte(1.0f, 0.95f, 0.8f, 0.2f), at(-29.0f + i * 2.0f, 4.8f, 1.5f));
  }
  for (int i = 0; i < 20; ++i) {
    s.add("bin", cylinder(0.25f, 0.25f, 0.8f, n(1000)), matte(0.2f, 0.25f, 0.2f, 0.5f),
          at(-27.0f + i * 3.0f, 0.0f, -4.6f));
  }
  for (int i = 0; i < 21; ++i) {
    s.add("sign", box({0.8f, 0.2f, 0.03f}, n(100)), matte(0.1f, 0.2f, 0.6f, 0.3f), at(-30.0f + i * 3.0f, 4.2f, -1.0f));
  }
  s.add("train", box({20.0f, 1.6f, 1.4f}, n(20000)), matte(0.6f, 0.62f, 0.65f, 0.35f), at(8.0f, 0.6f, 6.5f));

  for (int i = 0; i < 2; ++i) {  // two soldiers marching along the platform, out of step
    s.skeletons.push_back(soldier_skeleton(i * 1.7));
    Object& soldier = s.add("soldier", soldier_mesh(n(70000)), metal(0.8f, 0.82f, 0.85f, 0.3f));
    soldier.skeleton = i;
    const float lane = i ? 1.5f : -0.5f, lead = i ? 2.5f : 0.0f;
    soldier.animation = [lane, lead](double t) {
      const float x = march_x(t) + lead;
      return at(x, 0.0f, lane, march_heading(t));
    };
  }

  Light bulb;
  bulb.type = Light::Type::Spot;
  bulb.position = {0.0f, 4.9f, 0.5f};
  bulb.direction = Eigen::Vector3f(0.0f, -1.0f, 0.0f);
  bulb.color = {300.0f, 270.0f, 220.0f};
  bulb.cone_deg = 70.0f;
  s.lights.push_back(bulb);
  s.sky = {0.08f, 0.08f, 0.09f};
  s.ground = {0.05f, 0.04f, 0.04f};
  s.shadow_centre = {0.0f, 1.0f, 0.0f};
  s.shadow_radius = 30.0f;
  s.far_plane = 80.0f;
  s.reflection_distance = 10.0f;
  s.camera = [](double t) {  // follows the soldiers from the wall side of the platform
    const float x = march_x(t) + 1.0f;
    const auto sway = static_cast<float>(1.5 * std::sin(0.3 * t));
    return CameraPose{{x - 3.0f + sway, 1.6f, -3.2f}, {x + 1.0f, 1.0f, 0.5f}, 60.0f};
  };
  return s;
}

}  // namespace demo
