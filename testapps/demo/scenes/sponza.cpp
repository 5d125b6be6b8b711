// Sponza-like atrium: ~260k triangles, ~380 objects; the sun plus a candle spot light,
// metallic ornaments and a slightly reflective floor (paper, Table 3).
#include <cmath>

#include "scenes/registry.hpp"
#include "scenes/scene_kit.hpp"

namespace demo {

Scene make_sponza(float detail) {
  using namespace kit;
  const auto n = [detail](int triangles) { return scaled(triangles, detail); };
  Scene s;
  s.name = "sponza";
  const Material stone = matte(0.72f, 0.66f, 0.56f, 0.7f);
  s.add("floor", plane(32.0f, 14.0f, n(8000)), reflective(0.5f, 0.45f, 0.4f, 0.35f, 0.15f));
  for (float z : {-7.0f, 7.0f}) s.add("wall", box({16.0f, 6.0f, 0.3f}, n(1000)), stone, at(0.0f, 6.0f, z));
  for (float x : {-16.0f, 16.0f}) s.add("wall", box({0.3f, 6.0f, 7.0f}, n(1000)), stone, at(x, 6.0f, 0.0f));
  for (float z : {-5.5f, 5.5f}) s.add("gallery", box({15.5f, 0.2f, 1.5f}, n(1000)), stone, at(0.0f, 5.0f, z));

  // Two storeys of arcades on both sides: columns, capitals and arches.
  for (int storey = 0; storey < 2; ++storey) {
    const float y = storey * 5.2f, height = storey ? 3.6f : 4.4f;
    for (float z : {-4.0f, 4.0f}) {
      for (int i = 0; i < 10; ++i) {
        const float x = -13.5f + i * 3.0f;
        s.add("column", cylinder(0.35f, 0.3f, height, n(2200)), stone, at(x, y, z));
        s.add("capital", box({0.45f, 0.15f, 0.45f}, n(200)), stone, at(x, y + height, z));
        if (i < 9) {
          s.add("arch", torus(1.5f, 0.2f, n(1500)), stone,
                Eigen::Translation3f(x + 1.5f, y + height, z) * Eigen::AngleAxisf(1.5708f, Eigen::Vector3f::UnitX()));
        }
      }
    }
  }
  Rng rng(381);
  for (int i = 0; i < 20; ++i) {  // drapes hanging from the gallery
    const float x = -13.5f + (i % 10) * 3.0f + 1.5f, z = i < 10 ? -4.3f : 4.3f;
    const float phase = rng.uniform(0.0f, 6.0f);
    Mesh drape = terrain(2.4f, n(1500), [phase](float u, float v) {
      return 0.12f * std::sin(4.0f * u + phase) + 0.05f * std::sin(3.0f * v);
    });
    const Eigen::Vector3f colour = i % 2 ? Eigen::Vector3f(0.6f, 0.1f, 0.1f) : Eigen::Vector3f(0.15f, 0.35f, 0.2f);
    s.add("drape", drape, matte(colour.x(), colour.y(), colour.z(), 0.9f),
          Eigen::Translation3f(x, 3.6f, z) * Eigen::AngleAxisf(1.5708f, Eigen::Vector3f::UnitX()));
  }
  const std::vector<Eigen::Vector2f> vase_profile{{0.0f, 0.0f}, {0.25f, 0.02f}, {0.35f, 0.3f},
                                                  {0.2f, 0.6f}, {0.28f, 0.8f},  {0.0f, 0.78f}};
  for (int i = 0; i < 60; ++i) {
    const float x = rng.uniform(-14.0f, 14.0f), z = rng.uniform(-2.5f, 2.5f);
    s.add("vase", lathe(vase_profile, n(500)), matte(0.6f, 0.35f, 0.2f, 0.5f),
          at(x, 0.0f, z, 0.0f, rng.uniform(0.8f, 1.5f)));
  }
  for (int i = 0; i < 30; ++i) {  // metallic ornaments on the columns' bases
    const float x = -13.5f + (i % 10) * 3.0f, z = i < 10 ? -3.4f : (i < 20 ? 3.4f : 0.0f);
    const Mesh ornament = i % 2 ? sphere(0.3f, n(600)) : torus_knot(2, 3, 0.35f, 0.08f, n(600));
    s.add("ornament", ornament, metal(0.95f, 0.75f, 0.35f, 0.2f), at(x, 0.8f, z));
  }
  for (int i = 0; i < 148; ++i) {  // benches, crates and steps along the walls
    const float x = rng.uniform(-15.0f, 15.0f), z = (i % 2 ? 1.0f : -1.0f) * rng.uniform(5.0f, 6.6f);
    const Eigen::Vector3f half(rng.uniform(0.2f, 0.6f), rng.uniform(0.1f, 0.4f), rng.uniform(0.2f, 0.4f));
    s.add("crate", box(half, n(100)), matte(0.45f, 0.35f, 0.25f), at(x, half.y(), z, rng.uniform(0.0f, 3.0f)));
  }

  Light sun;
  sun.type = Light::Type::Directional;
  sun.direction = Eigen::Vector3f(0.3f, -0.9f, 0.25f).normalized();
  sun.color = {3.2f, 3.0f, 2.7f};
  s.lights.push_back(sun);
  Light candle;
  candle.type = Light::Type::Spot;
  candle.position = {0.0f, 1.5f, 0.0f};
  candle.direction = Eigen::Vector3f(0.0f, -1.0f, 0.0f);
  candle.color = {12.0f, 6.0f, 2.0f};
  candle.cone_deg = 80.0f;
  s.lights.push_back(candle);
  s.sky = {0.35f, 0.4f, 0.5f};
  s.ground = {0.15f, 0.12f, 0.1f};
  s.shadow_centre = {0.0f, 4.0f, 0.0f};
  s.shadow_radius = 19.0f;
  s.far_plane = 80.0f;
  s.reflection_distance = 10.0f;
  s.camera = [](double t) {
    const auto x = static_cast<float>(12.0 * std::sin(0.15 * t));
    return CameraPose{{x, 1.8f, -1.0f}, {x - 6.0f, 3.0f, 3.0f}, 65.0f};
  };
  return s;
}

}  // namespace demo
