// A walking soldier: an 11-bone rig, its skinned mesh and a walk cycle driven by time.
#pragma once
#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "mesh.hpp"

namespace demo {

inline constexpr int kMaxBones = 16;  // matches MAX_BONES in scene.vert

struct Bone {
  int parent;             // -1: root
  Eigen::Vector3f pivot;  // joint position in the rest pose (model space)
};

struct Skeleton {
  std::vector<Bone> bones;
  double phase = 0.0;  // walk-cycle offset, so two soldiers do not march in lockstep
  // Skinning matrices (model space, rest pose -> posed) at time t, one per bone.
  std::vector<Eigen::Matrix4f> pose(double t) const;
};

Skeleton soldier_skeleton(double phase);
// A soldier of about `triangles` triangles skinned to soldier_skeleton(): ~1.8 units tall.
Mesh soldier_mesh(int triangles);

}  // namespace demo
