// A procedural scene: geometry, materials, lights, and its camera path and animation as
// functions of time, so that frame N always looks the same.
#pragma once
#include <Eigen/Geometry>
#include <functional>
#include <string>
#include <vector>

#include "camera.hpp"
#include "mesh.hpp"
#include "skeleton.hpp"

namespace demo {

struct Material {
  Eigen::Vector3f albedo{0.7f, 0.7f, 0.7f};
  float roughness = 0.6f;
  bool metal = false;         // drawn by the metals pass (importance-sampled environment)
  float reflectivity = 0.0f;  // screen-space reflection strength (reflections pass)
};

struct Object {
  std::string name;
  uint32_t first_index = 0;
  uint32_t index_count = 0;
  Material material;
  Eigen::Affine3f transform = Eigen::Affine3f::Identity();
  std::function<Eigen::Affine3f(double t)> animation;  // empty: static
  int skeleton = -1;                                   // index into Scene::skeletons, -1: rigid
};

struct Light {
  enum class Type { Directional, Spot, Point };
  Type type = Type::Point;
  Eigen::Vector3f position = Eigen::Vector3f::Zero();     // spot and point
  Eigen::Vector3f direction = -Eigen::Vector3f::UnitY();  // directional and spot: where it shines
  Eigen::Vector3f color = Eigen::Vector3f::Ones();        // radiance (directional) or intensity
  float cone_deg = 45.0f;                                 // spot: half angle
};

struct Scene {
  std::string name;
  Mesh geometry;  // every object's triangles, one shared vertex/index buffer
  std::vector<Object> objects;
  std::vector<Light> lights;  // lights[0] casts the shadow map
  std::vector<Skeleton> skeletons;
  Eigen::Vector3f sky{0.5f, 0.6f, 0.8f}, ground{0.2f, 0.18f, 0.15f};  // ambient environment
  Eigen::Vector3f shadow_centre = Eigen::Vector3f::Zero();            // what the shadow map covers
  float shadow_radius = 20.0f;
  float far_plane = 100.0f;
  float reflection_distance = 10.0f;  // how far screen-space reflection rays travel
  std::function<CameraPose(double t)> camera;

  // Adds `mesh` as a new object and returns it for the caller to fill in.
  Object& add(std::string object_name, const Mesh& mesh, const Material& material,
              const Eigen::Affine3f& transform = Eigen::Affine3f::Identity());
  bool has_metals() const;
  bool has_reflective_surfaces() const;
  size_t triangle_count() const { return geometry.triangles(); }
  size_t size_bytes() const;  // vertex + index data as uploaded
};

}  // namespace demo
