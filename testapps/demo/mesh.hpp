// Procedural triangle meshes: the building blocks of the four scenes. Every builder takes a
// triangle budget and picks its tessellation from it, so scenes scale with --detail.
#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <vector>

namespace demo {

struct Vertex {
  float position[3];
  float normal[3];
  uint8_t bones[4];  // two bone indices used (skinned meshes only), two padding bytes
  float weight;      // weight of bones[0]; bones[1] gets 1 - weight
};
static_assert(sizeof(Vertex) == 32);

struct Mesh {
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;

  size_t triangles() const { return indices.size() / 3; }
  // Appends `other` transformed by `transform` (rigid + uniform scale).
  void append(const Mesh& other, const Eigen::Affine3f& transform = Eigen::Affine3f::Identity());
  // Binds every vertex to `bone` with full weight.
  void bind_to_bone(uint8_t bone);
};

struct SurfacePoint {
  Eigen::Vector3f position;
  Eigen::Vector3f normal;  // zero: computed numerically from neighbouring positions
};
using Surface = std::function<SurfacePoint(float u, float v)>;  // u, v in [0, 1]

// A (u_segments x v_segments) grid over the unit square, mapped by `surface`.
Mesh parametric(int u_segments, int v_segments, const Surface& surface);
// Splits a triangle budget into grid segments with the given u:v aspect ratio.
void segments_for(int triangles, float aspect, int& u_segments, int& v_segments);

Mesh plane(float size_x, float size_z, int triangles);  // y = 0, normal +y, centred
Mesh terrain(float size, int triangles, const std::function<float(float x, float z)>& height);
Mesh box(const Eigen::Vector3f& half_extent, int triangles);
Mesh sphere(float radius, int triangles);
Mesh cylinder(float radius_bottom, float radius_top, float height, int triangles);  // y in [0, h]
Mesh torus(float major, float minor, int triangles);                                // in the xz plane
Mesh torus_knot(int p, int q, float radius, float tube, int triangles);
// Surface of revolution around y of the profile (radius, y) pairs, bottom to top.
Mesh lathe(const std::vector<Eigen::Vector2f>& profile, int triangles);

}  // namespace demo
