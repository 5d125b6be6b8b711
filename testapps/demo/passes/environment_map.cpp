#include "passes/environment_map.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace demo {

namespace {
float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// Direction through texel (s, t) in [-1, 1] of cube face `face` (GL's face orientation table).
Eigen::Vector3f face_direction(int face, float s, float t) {
  switch (face) {
    case 0:
      return {1.0f, -t, -s};
    case 1:
      return {-1.0f, -t, s};
    case 2:
      return {s, 1.0f, t};
    case 3:
      return {s, -1.0f, -t};
    case 4:
      return {s, -t, 1.0f};
    default:
      return {-s, -t, -1.0f};
  }
}
}  // namespace

Eigen::Vector3f EnvironmentMap::radiance(const Eigen::Vector3f& direction, const Eigen::Vector3f& sky,
                                         const Eigen::Vector3f& ground) {
  const Eigen::Vector3f d = direction.normalized();
  const Eigen::Vector3f base = ground + (sky - ground) * smoothstep(-0.3f, 0.3f, d.y());
  const float azimuth = std::atan2(d.z(), d.x()) * (4.0f / std::numbers::pi_v<float>);
  const float fraction = azimuth - std::floor(azimuth);
  const float panels = (fraction >= 0.75f ? 1.0f : 0.0f) * smoothstep(0.05f, 0.35f, d.y());
  return base + panels * 4.0f * (sky + Eigen::Vector3f::Constant(0.2f));
}

GLuint EnvironmentMap::texture(const Eigen::Vector3f& sky, const Eigen::Vector3f& ground) {
  if (texture_ && sky == sky_ && ground == ground_) return texture_;
  sky_ = sky;
  ground_ = ground;
  if (!texture_) glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_CUBE_MAP, texture_);
  std::vector<float> texels(static_cast<size_t>(kFaceSize) * kFaceSize * 3);
  for (int face = 0; face < 6; ++face) {
    for (int y = 0; y < kFaceSize; ++y) {
      for (int x = 0; x < kFaceSize; ++x) {
        const float s = 2.0f * (x + 0.5f) / kFaceSize - 1.0f, t = 2.0f * (y + 0.5f) / kFaceSize - 1.0f;
        const Eigen::Vector3f c = radiance(face_direction(face, s, t), sky, ground);
        std::copy(c.data(), c.data() + 3, &texels[(static_cast<size_t>(y) * kFaceSize + x) * 3]);
      }
    }
    glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, 0, GL_RGB16F, kFaceSize, kFaceSize, 0, GL_RGB, GL_FLOAT,
                 texels.data());
  }
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTexParameteri(GL_TEXTURE_CUBE_MAP, wrap, GL_CLAMP_TO_EDGE);
  return texture_;
}

EnvironmentMap::~EnvironmentMap() {
  if (texture_) glDeleteTextures(1, &texture_);
}

}  // namespace demo
