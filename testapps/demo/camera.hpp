// Camera poses and the projection/view matrices built from them.
#pragma once
#include <Eigen/Geometry>

namespace demo {

struct CameraPose {
  Eigen::Vector3f eye;
  Eigen::Vector3f target;
  float vertical_fov_deg = 60.0f;
};

Eigen::Matrix4f look_at(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                        const Eigen::Vector3f& up = Eigen::Vector3f::UnitY());
Eigen::Matrix4f perspective(float vertical_fov_deg, float aspect, float near_plane, float far_plane);
Eigen::Matrix4f orthographic(float half_width, float half_height, float near_plane, float far_plane);

}  // namespace demo
