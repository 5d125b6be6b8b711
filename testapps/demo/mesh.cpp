#include "mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demo {
namespace {
constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kTau = 2.0f * kPi;

Eigen::Vector3f numeric_normal(const Surface& surface, float u, float v, float du, float dv) {
  const auto p = [&](float uu, float vv) { return surface(uu, vv).position; };
  const Eigen::Vector3f tu = p(std::min(u + du, 1.0f), v) - p(std::max(u - du, 0.0f), v);
  const Eigen::Vector3f tv = p(u, std::min(v + dv, 1.0f)) - p(u, std::max(v - dv, 0.0f));
  Eigen::Vector3f n = tu.cross(tv);
  const float length = n.norm();
  return length > 1e-12f ? Eigen::Vector3f(n / length) : Eigen::Vector3f::UnitY();
}

Vertex make_vertex(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  return Vertex{{p.x(), p.y(), p.z()}, {n.x(), n.y(), n.z()}, {0, 0, 0, 0}, 1.0f};
}
}  // namespace

void Mesh::append(const Mesh& other, const Eigen::Affine3f& transform) {
  const auto base = static_cast<uint32_t>(vertices.size());
  const Eigen::Matrix3f rotation = transform.linear();
  for (Vertex v : other.vertices) {
    const Eigen::Vector3f p = transform * Eigen::Vector3f(v.position[0], v.position[1], v.position[2]);
    const Eigen::Vector3f n = (rotation * Eigen::Vector3f(v.normal[0], v.normal[1], v.normal[2])).normalized();
    std::copy_n(p.data(), 3, v.position);
    std::copy_n(n.data(), 3, v.normal);
    vertices.push_back(v);
  }
  for (uint32_t i : other.indices) indices.push_back(base + i);
}

void Mesh::bind_to_bone(uint8_t bone) {
  for (Vertex& v : vertices) {
    v.bones[0] = v.bones[1] = bone;
    v.weight = 1.0f;
  }
}

void segments_for(int triangles, float aspect, int& u_segments, int& v_segments) {
  const float quads = std::max(1.0f, triangles / 2.0f);
  v_segments = std::max(1, static_cast<int>(std::lround(std::sqrt(quads / aspect))));
  u_segments = std::max(1, static_cast<int>(std::lround(quads / v_segments)));
}

Mesh parametric(int u_segments, int v_segments, const Surface& surface) {
  Mesh mesh;
  const float du = 0.5f / u_segments, dv = 0.5f / v_segments;
  for (int j = 0; j <= v_segments; ++j) {
    for (int i = 0; i <= u_segments; ++i) {
      const float u = static_cast<float>(i) / u_segments, v = static_cast<float>(j) / v_segments;
      SurfacePoint point = surface(u, v);
      if (point.normal.isZero()) point.normal = numeric_normal(surface, u, v, du, dv);
      mesh.vertices.push_back(make_vertex(point.position, point.normal.normalized()));
    }
  }
  const auto row = static_cast<uint32_t>(u_segments + 1);
  for (uint32_t j = 0; j < static_cast<uint32_t>(v_segments); ++j) {
    for (uint32_t i = 0; i < static_cast<uint32_t>(u_segments); ++i) {
      const uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, d});
    }
  }
  return mesh;
}

Mesh plane(float size_x, float size_z, int triangles) {
  int nu, nv;
  segments_for(triangles, size_x / size_z, nu, nv);
  return parametric(nu, nv, [=](float u, float v) {
    return SurfacePoint{{(u - 0.5f) * size_x, 0.0f, (v - 0.5f) * size_z}, Eigen::Vector3f::UnitY()};
  });
}

Mesh terrain(float size, int triangles, const std::function<float(float, float)>& height) {
  int nu, nv;
  segments_for(triangles, 1.0f, nu, nv);
  return parametric(nu, nv, [=](float u, float v) {
    const float x = (u - 0.5f) * size, z = (v - 0.5f) * size;
    return SurfacePoint{{x, height(x, z), z}, Eigen::Vector3f::Zero()};
  });
}

Mesh box(const Eigen::Vector3f& half, int triangles) {
  Mesh mesh;
  const int per_face = std::max(2, triangles / 6);
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      int nu, nv;
      segments_for(per_face, half[a] / half[b], nu, nv);
      Eigen::Vector3f normal = Eigen::Vector3f::Zero();
      normal[axis] = sign;
      mesh.append(parametric(nu, nv, [=](float u, float v) {
        Eigen::Vector3f p;
        p[axis] = sign * half[axis];
        p[a] = (2.0f * u - 1.0f) * half[a];
        p[b] = (2.0f * v - 1.0f) * half[b];
        return SurfacePoint{p, normal};
      }));
    }
  }
  return mesh;
}

Mesh sphere(float radius, int triangles) {
  int nu, nv;
  segments_for(triangles, 2.0f, nu, nv);
  return parametric(std::max(nu, 3), std::max(nv, 2), [=](float u, float v) {
    const float phi = u * kTau, theta = v * kPi;
    const Eigen::Vector3f n(std::sin(theta) * std::cos(phi), -std::cos(theta), std::sin(theta) * std::sin(phi));
    return SurfacePoint{radius * n, n};
  });
}

Mesh cylinder(float r0, float r1, float height, int triangles) {
  int nu, nv;
  segments_for(triangles, 4.0f, nu, nv);
  const float slope = (r0 - r1) / height;
  return parametric(std::max(nu, 3), nv, [=](float u, float v) {
    const float phi = u * kTau, r = r0 + (r1 - r0) * v;
    const Eigen::Vector3f n = Eigen::Vector3f(std::cos(phi), slope, std::sin(phi)).normalized();
    return SurfacePoint{{r * std::cos(phi), v * height, r * std::sin(phi)}, n};
  });
}

Mesh torus(float major, float minor, int triangles) {
  int nu, nv;
  segments_for(triangles, major / minor, nu, nv);
  return parametric(std::max(nu, 3), std::max(nv, 3), [=](float u, float v) {
    const float phi = u * kTau, theta = v * kTau;
    const Eigen::Vector3f ring(std::cos(phi), 0.0f, std::sin(phi));
    const Eigen::Vector3f n = ring * std::cos(theta) + Eigen::Vector3f::UnitY() * std::sin(theta);
    return SurfacePoint{ring * major + n * minor, n};
  });
}

Mesh torus_knot(int p, int q, float radius, float tube, int triangles) {
  int nu, nv;
  segments_for(triangles, 24.0f, nu, nv);
  const auto curve = [=](float t) {
    const float r = radius * (2.0f + std::cos(q * t)) / 3.0f;
    return Eigen::Vector3f(r * std::cos(p * t), radius * std::sin(q * t) / 3.0f, r * std::sin(p * t));
  };
  return parametric(std::max(nu, 8), std::max(nv, 3), [=](float u, float v) {
    const float t = u * kTau, eps = 1e-3f;
    const Eigen::Vector3f centre = curve(t);
    const Eigen::Vector3f tangent = (curve(t + eps) - curve(t - eps)).normalized();
    const Eigen::Vector3f side = tangent.cross(Eigen::Vector3f::UnitY()).normalized();
    const Eigen::Vector3f up = side.cross(tangent);
    const float theta = v * kTau;
    const Eigen::Vector3f n = side * std::cos(theta) + up * std::sin(theta);
    return SurfacePoint{centre + n * tube, n};
  });
}

Mesh lathe(const std::vector<Eigen::Vector2f>& profile, int triangles) {
  int nu, nv;
  segments_for(triangles, 2.0f, nu, nv);
  const auto last = static_cast<float>(profile.size() - 1);
  return parametric(std::max(nu, 3), std::max(nv, 1), [=](float u, float v) {
    // Linear interpolation along the profile; numeric normals.
    const float s = v * last;
    const auto i = std::min(static_cast<size_t>(s), profile.size() - 2);
    const Eigen::Vector2f rp = profile[i] + (profile[i + 1] - profile[i]) * (s - static_cast<float>(i));
    const float phi = u * kTau;
    return SurfacePoint{{rp.x() * std::cos(phi), rp.y(), rp.x() * std::sin(phi)}, Eigen::Vector3f::Zero()};
  });
}

}  // namespace demo
