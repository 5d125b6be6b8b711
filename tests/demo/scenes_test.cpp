// Scene generation is GL-free: statistics against the paper's Table 3, detail scaling,
// determinism and mesh validity.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include "gpu_scene.hpp"
#include "scenes/registry.hpp"

namespace {

void check_mesh_valid(const demo::Scene& scene) {
  const auto vertex_count = scene.geometry.vertices.size();
  REQUIRE(scene.geometry.indices.size() % 3 == 0);
  for (uint32_t index : scene.geometry.indices) REQUIRE(index < vertex_count);
  for (const demo::Vertex& v : scene.geometry.vertices) {
    for (float c : v.position) REQUIRE(std::isfinite(c));
    const float length = std::sqrt(v.normal[0] * v.normal[0] + v.normal[1] * v.normal[1] + v.normal[2] * v.normal[2]);
    REQUIRE(length == Approx(1.0f).margin(1e-3));
    REQUIRE(v.weight >= 0.0f);
    REQUIRE(v.weight <= 1.0f);
  }
  uint64_t covered = 0;
  for (const demo::Object& o : scene.objects) {
    REQUIRE(o.index_count > 0);
    REQUIRE(o.first_index + o.index_count <= scene.geometry.indices.size());
    covered += o.index_count;
  }
  CHECK(covered == scene.geometry.indices.size());
}

struct PaperRow {
  const char* name;
  double triangles;
  size_t objects;
};

}  // namespace

TEST_CASE("scenes match the paper's Table 3 at detail 1", "[demo][scenes]") {
  const PaperRow rows[] = {
      {"hall", 229.4e3, 23}, {"sponza", 262.1e3, 381}, {"valley", 143.3e3, 61}, {"subway", 526.6e3, 453}};
  for (const PaperRow& row : rows) {
    INFO(row.name);
    const auto scene = demo::make_scene(row.name, 1.0f);
    REQUIRE(scene);
    CHECK(scene->objects.size() == row.objects);
    CHECK(static_cast<double>(scene->triangle_count()) == Approx(row.triangles).epsilon(0.05));
    check_mesh_valid(*scene);
  }
}

TEST_CASE("scene character: lights, metals, reflective floors, animation", "[demo][scenes]") {
  const auto hall = demo::make_scene("hall", 0.01f), sponza = demo::make_scene("sponza", 0.01f);
  const auto valley = demo::make_scene("valley", 0.01f), subway = demo::make_scene("subway", 0.01f);
  CHECK(hall->lights.front().type == demo::Light::Type::Spot);
  CHECK(hall->has_metals());
  CHECK(hall->has_reflective_surfaces());
  CHECK(sponza->lights.size() == 2);
  CHECK(sponza->lights.front().type == demo::Light::Type::Directional);
  CHECK(sponza->has_metals());
  CHECK(valley->lights.front().type == demo::Light::Type::Directional);
  CHECK_FALSE(valley->has_metals());
  CHECK_FALSE(valley->has_reflective_surfaces());
  CHECK(subway->skeletons.size() == 2);
  int skinned_metal = 0;
  for (const demo::Object& o : subway->objects) skinned_metal += o.skeleton >= 0 && o.material.metal && o.animation;
  CHECK(skinned_metal == 2);
}

TEST_CASE("--detail scales triangles, not objects, down to its extreme", "[demo][scenes]") {
  for (std::string_view name : demo::scene_names()) {
    INFO(name);
    const auto full = demo::make_scene(name, 1.0f), small = demo::make_scene(name, 0.05f);
    const auto tiny = demo::make_scene(name, 0.001f);
    CHECK(small->objects.size() == full->objects.size());
    CHECK(tiny->objects.size() == full->objects.size());
    CHECK(small->triangle_count() < full->triangle_count() / 8);
    CHECK(tiny->triangle_count() <= small->triangle_count());
    check_mesh_valid(*tiny);
  }
  CHECK_FALSE(demo::make_scene("atlantis", 1.0f));
}

TEST_CASE("scenes and their animation are functions of time only", "[demo][scenes]") {
  const auto a = demo::make_scene("subway", 0.02f), b = demo::make_scene("subway", 0.02f);
  REQUIRE(a->geometry.vertices.size() == b->geometry.vertices.size());
  CHECK(std::memcmp(a->geometry.vertices.data(), b->geometry.vertices.data(),
                    a->geometry.vertices.size() * sizeof(demo::Vertex)) == 0);
  const auto pose_a = demo::ScenePose::at(*a, 3.25), pose_b = demo::ScenePose::at(*b, 3.25);
  CHECK(pose_a.skeleton_bones == pose_b.skeleton_bones);
  CHECK(pose_a.object_transforms == pose_b.object_transforms);
  CHECK(a->camera(3.25).eye == b->camera(3.25).eye);
  const auto later = demo::ScenePose::at(*a, 3.5);
  CHECK(later.skeleton_bones != pose_a.skeleton_bones);  // the soldiers walk
  for (const auto& bones : later.skeleton_bones) {
    for (const auto& m : bones) CHECK(m.allFinite());
  }
  // Far along the path (a long run): still finite and on the platform.
  const auto far = demo::ScenePose::at(*a, 1e6);
  for (const auto& m : far.object_transforms) CHECK(m.allFinite());
  CHECK(std::abs(far.object_transforms.back()(0, 3)) <= 13.0f);
}
