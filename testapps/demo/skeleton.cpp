#include "skeleton.hpp"

#include <algorithm>
#include <cmath>

namespace demo {
namespace {
enum BoneId { Hips, Spine, Head, LUpperArm, LForearm, RUpperArm, RForearm, LThigh, LShin, RThigh, RShin, BoneCount };

// Joint angles (radians, about x) of the walk cycle at phase `w`.
std::array<float, BoneCount> walk_angles(double w) {
  std::array<float, BoneCount> a{};
  const auto s = static_cast<float>(std::sin(w)), c = static_cast<float>(std::cos(w));
  a[Spine] = 0.05f * c;
  a[LThigh] = 0.5f * s;
  a[RThigh] = -0.5f * s;
  a[LShin] = 0.4f * std::max(0.0f, -c);
  a[RShin] = 0.4f * std::max(0.0f, c);
  a[LUpperArm] = -0.4f * s;
  a[RUpperArm] = 0.4f * s;
  a[LForearm] = -0.3f;
  a[RForearm] = -0.3f;
  return a;
}

// A limb hanging down from `joint`, weighted to `bone`, blending into `parent` at the joint.
Mesh limb(float radius, float length, const Eigen::Vector3f& joint, uint8_t bone, uint8_t parent, int triangles) {
  Mesh part = cylinder(radius, radius * 0.85f, length, triangles);
  for (Vertex& v : part.vertices) {
    const float from_joint = v.position[1] / length;  // 0 at the joint end
    v.bones[0] = bone;
    v.bones[1] = parent;
    v.weight = std::clamp(0.5f + from_joint * 2.5f, 0.5f, 1.0f);
  }
  Mesh placed;
  placed.append(part, Eigen::Translation3f(joint) * Eigen::AngleAxisf(3.14159265f, Eigen::Vector3f::UnitX()));
  return placed;
}
}  // namespace

Skeleton soldier_skeleton(double phase) {
  Skeleton s;
  s.phase = phase;
  s.bones.resize(BoneCount);
  s.bones[Hips] = {-1, {0.0f, 1.0f, 0.0f}};
  s.bones[Spine] = {Hips, {0.0f, 1.05f, 0.0f}};
  s.bones[Head] = {Spine, {0.0f, 1.55f, 0.0f}};
  s.bones[LUpperArm] = {Spine, {-0.25f, 1.5f, 0.0f}};
  s.bones[LForearm] = {LUpperArm, {-0.25f, 1.2f, 0.0f}};
  s.bones[RUpperArm] = {Spine, {0.25f, 1.5f, 0.0f}};
  s.bones[RForearm] = {RUpperArm, {0.25f, 1.2f, 0.0f}};
  s.bones[LThigh] = {Hips, {-0.12f, 0.95f, 0.0f}};
  s.bones[LShin] = {LThigh, {-0.12f, 0.5f, 0.0f}};
  s.bones[RThigh] = {Hips, {0.12f, 0.95f, 0.0f}};
  s.bones[RShin] = {RThigh, {0.12f, 0.5f, 0.0f}};
  return s;
}

std::vector<Eigen::Matrix4f> Skeleton::pose(double t) const {
  const double w = phase + t * 4.0;  // about 0.6 strides per second
  const auto angles = walk_angles(w);
  std::vector<Eigen::Matrix4f> global(bones.size());
  for (size_t i = 0; i < bones.size(); ++i) {
    const Bone& b = bones[i];
    // Rotation about the joint in model space; parents come first in the bone list.
    const float angle = i < angles.size() ? angles[i] : 0.0f;
    Eigen::Affine3f local = Eigen::Translation3f(b.pivot) * Eigen::AngleAxisf(angle, Eigen::Vector3f::UnitX()) *
                            Eigen::Translation3f(-b.pivot);
    if (b.parent < 0) {
      // The root bobs with the stride.
      local = Eigen::Translation3f(0.0f, 0.03f * static_cast<float>(std::abs(std::sin(w))), 0.0f) * local;
    }
    global[i] = b.parent < 0 ? local.matrix() : Eigen::Matrix4f(global[b.parent] * local.matrix());
  }
  return global;
}

Mesh soldier_mesh(int triangles) {
  const int t = std::max(triangles / 19, 12);  // 19 shares of the budget, see the parts below
  Mesh m;
  Mesh torso = cylinder(0.2f, 0.24f, 0.5f, 3 * t);
  torso.bind_to_bone(Spine);
  m.append(torso, Eigen::Affine3f(Eigen::Translation3f(0.0f, 1.0f, 0.0f)));
  Mesh pelvis = sphere(0.19f, t);
  pelvis.bind_to_bone(Hips);
  m.append(pelvis, Eigen::Affine3f(Eigen::Translation3f(0.0f, 0.98f, 0.0f)));
  Mesh head = sphere(0.13f, 2 * t);
  head.bind_to_bone(Head);
  m.append(head, Eigen::Affine3f(Eigen::Translation3f(0.0f, 1.7f, 0.0f)));
  Mesh helmet = torus(0.14f, 0.03f, t);
  helmet.bind_to_bone(Head);
  m.append(helmet, Eigen::Affine3f(Eigen::Translation3f(0.0f, 1.75f, 0.0f)));
  const Skeleton s = soldier_skeleton(0.0);
  const auto add_limb = [&](int bone, float radius, float length, int tris) {
    m.append(limb(radius, length, s.bones[bone].pivot, static_cast<uint8_t>(bone),
                  static_cast<uint8_t>(s.bones[bone].parent), tris));
  };
  add_limb(LUpperArm, 0.06f, 0.3f, t);
  add_limb(RUpperArm, 0.06f, 0.3f, t);
  add_limb(LForearm, 0.05f, 0.3f, t);
  add_limb(RForearm, 0.05f, 0.3f, t);
  add_limb(LThigh, 0.09f, 0.45f, 2 * t);
  add_limb(RThigh, 0.09f, 0.45f, 2 * t);
  add_limb(LShin, 0.07f, 0.48f, 2 * t);
  add_limb(RShin, 0.07f, 0.48f, 2 * t);
  return m;
}

}  // namespace demo
