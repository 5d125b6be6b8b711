#include "camera.hpp"

#include <cmath>
#include <numbers>

namespace demo {

Eigen::Matrix4f look_at(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, const Eigen::Vector3f& up) {
  const Eigen::Vector3f f = (target - eye).normalized();
  // Looking straight along `up` would make the basis degenerate: pick another up then.
  const Eigen::Vector3f safe_up = std::abs(f.dot(up)) > 0.999f ? Eigen::Vector3f::UnitZ() : up;
  const Eigen::Vector3f s = f.cross(safe_up).normalized();
  const Eigen::Vector3f u = s.cross(f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Eigen::Matrix4f perspective(float fov_deg, float aspect, float n, float f) {
  const float t = 1.0f / std::tan(fov_deg * std::numbers::pi_v<float> / 360.0f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (f + n) / (n - f);
  m(2, 3) = 2.0f * f * n / (n - f);
  m(3, 2) = -1.0f;
  return m;
}

Eigen::Matrix4f orthographic(float hw, float hh, float n, float f) {
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m(0, 0) = 1.0f / hw;
  m(1, 1) = 1.0f / hh;
  m(2, 2) = -2.0f / (f - n);
  m(2, 3) = -(f + n) / (f - n);
  return m;
}

}  // namespace demo
