#include "scene.hpp"

#include <algorithm>

namespace demo {

Object& Scene::add(std::string object_name, const Mesh& mesh, const Material& material,
                   const Eigen::Affine3f& transform) {
  Object object;
  object.name = std::move(object_name);
  object.first_index = static_cast<uint32_t>(geometry.indices.size());
  object.index_count = static_cast<uint32_t>(mesh.indices.size());
  object.material = material;
  object.transform = transform;
  geometry.append(mesh);
  objects.push_back(std::move(object));
  return objects.back();
}

bool Scene::has_metals() const {
  return std::any_of(objects.begin(), objects.end(), [](const Object& o) { return o.material.metal; });
}

bool Scene::has_reflective_surfaces() const {
  return std::any_of(objects.begin(), objects.end(), [](const Object& o) { return o.material.reflectivity > 0.0f; });
}

size_t Scene::size_bytes() const {
  return geometry.vertices.size() * sizeof(Vertex) + geometry.indices.size() * sizeof(uint32_t);
}

}  // namespace demo
