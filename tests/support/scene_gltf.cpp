#include "support/scene_gltf.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

namespace facerig::test {
namespace {

constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

// Accessors appended to buffer 0, one view each, 4-byte aligned.
class Accessors {
 public:
  explicit Accessors(tinygltf::Model* model) : model_(model) {
    if (model_->buffers.empty()) model_->buffers.emplace_back();
  }
  int Add(const void* data, std::size_t bytes, std::size_t count, int component_type, int type, int target = 0) {
    std::vector<unsigned char>& buffer = model_->buffers[0].data;
    while (buffer.size() % 4 != 0) buffer.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.size();
    view.byteLength = bytes;
    view.target = target;
    buffer.resize(buffer.size() + bytes);
    std::memcpy(buffer.data() + view.byteOffset, data, bytes);
    model_->bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(model_->bufferViews.size()) - 1;
    accessor.componentType = component_type;
    accessor.count = count;
    accessor.type = type;
    model_->accessors.push_back(accessor);
    return static_cast<int>(model_->accessors.size()) - 1;
  }
  int AddVec3(const std::vector<glm::vec3>& values) {
    const int index = Add(values.data(), values.size() * sizeof(glm::vec3), values.size(), kFloat,
                          TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
    glm::vec3 lo(0.0f), hi(0.0f);
    if (!values.empty()) lo = hi = values.front();
    for (const glm::vec3& v : values) lo = glm::min(lo, v), hi = glm::max(hi, v);
    model_->accessors.back().minValues = {lo.x, lo.y, lo.z};
    model_->accessors.back().maxValues = {hi.x, hi.y, hi.z};
    return index;
  }

 private:
  tinygltf::Model* model_;
};

tinygltf::Primitive MeshPrimitive(const SceneMesh& mesh, int material, Accessors* accessors) {
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.material = material;
  primitive.attributes["POSITION"] = accessors->AddVec3(mesh.positions);
  primitive.indices = accessors->Add(mesh.triangles.data(), mesh.triangles.size() * sizeof(Triangle),
                                     mesh.triangles.size() * 3, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                     TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  if (!mesh.joints.empty()) {
    primitive.attributes["JOINTS_0"] =
        accessors->Add(mesh.joints.data(), mesh.joints.size() * sizeof(mesh.joints[0]), mesh.joints.size(),
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.attributes["WEIGHTS_0"] =
        accessors->Add(mesh.weights.data(), mesh.weights.size() * sizeof(glm::vec4), mesh.weights.size(), kFloat,
                       TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
  }
  if (!mesh.normals.empty()) primitive.attributes["NORMAL"] = accessors->AddVec3(mesh.normals);
  for (std::size_t t = 0; t < mesh.targets.size(); ++t) {
    primitive.targets.push_back({{"POSITION", accessors->AddVec3(mesh.targets[t].second)}});
    if (t < mesh.target_normals.size()) primitive.targets.back()["NORMAL"] = accessors->AddVec3(mesh.target_normals[t]);
  }
  return primitive;
}

tinygltf::Mesh GltfMesh(const SceneMesh& mesh, int material, Accessors* accessors) {
  tinygltf::Mesh out;
  out.name = mesh.name;
  out.primitives.push_back(MeshPrimitive(mesh, material, accessors));
  if (!mesh.targets.empty()) {
    tinygltf::Value::Array names;
    for (const auto& target : mesh.targets) names.emplace_back(target.first);
    out.extras = tinygltf::Value(tinygltf::Value::Object{{"targetNames", tinygltf::Value(names)}});
    out.weights.assign(mesh.targets.size(), 0.0);
  }
  return out;
}

tinygltf::Node GltfNode(const SceneNode& node) {
  tinygltf::Node out;
  out.name = node.name;
  out.mesh = node.mesh;
  out.skin = node.skin;
  out.children = node.children;
  if (node.translation != glm::dvec3(0.0)) out.translation = {node.translation.x, node.translation.y, node.translation.z};
  if (node.rotation != glm::dquat(1.0, 0.0, 0.0, 0.0)) {
    out.rotation = {node.rotation.x, node.rotation.y, node.rotation.z, node.rotation.w};
  }
  if (node.scale != glm::dvec3(1.0)) out.scale = {node.scale.x, node.scale.y, node.scale.z};
  return out;
}

glm::dmat4 LocalOf(const SceneNode& node) {
  return glm::translate(glm::dmat4(1.0), node.translation) * glm::mat4_cast(node.rotation) *
         glm::scale(glm::dmat4(1.0), node.scale);
}

int ParentOf(const SceneGltf& scene, int node) {
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    for (int child : scene.nodes[n].children) {
      if (child == node) return static_cast<int>(n);
    }
  }
  return -1;
}

}  // namespace

glm::dmat4 NodeWorld(const SceneGltf& scene, int node) {
  glm::dmat4 world(1.0);
  for (int n = node; n >= 0; n = ParentOf(scene, n)) world = LocalOf(scene.nodes[static_cast<std::size_t>(n)]) * world;
  return world;
}

void WriteSceneGltf(const std::filesystem::path& path, const SceneGltf& scene) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "facerig test exporter";
  Accessors accessors(&model);
  for (const SceneMesh& mesh : scene.meshes) {
    tinygltf::Material material;
    material.name = mesh.name + " material";
    material.pbrMetallicRoughness.baseColorFactor = {mesh.colour.r, mesh.colour.g, mesh.colour.b, mesh.colour.a};
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    model.materials.push_back(material);
    model.meshes.push_back(GltfMesh(mesh, static_cast<int>(model.materials.size()) - 1, &accessors));
  }
  for (const SceneNode& node : scene.nodes) model.nodes.push_back(GltfNode(node));
  for (const SceneSkin& skin : scene.skins) {
    tinygltf::Skin out;
    out.joints = skin.joints;
    if (!skin.inverse_binds.empty()) {
      out.inverseBindMatrices = accessors.Add(skin.inverse_binds.data(), skin.inverse_binds.size() * sizeof(glm::mat4),
                                              skin.inverse_binds.size(), kFloat, TINYGLTF_TYPE_MAT4);
    }
    model.skins.push_back(out);
  }
  tinygltf::Scene root;
  root.nodes = scene.roots;
  model.scenes.push_back(root);
  model.defaultScene = 0;
  model.buffers[0].name = "data";
  const bool binary = path.extension() == ".glb";
  tinygltf::TinyGLTF writer;
  writer.SetImageWriter(nullptr, nullptr);
  if (!writer.WriteGltfSceneToFile(&model, path.string(), false, true, !binary, binary)) {
    throw std::runtime_error("could not write " + path.string());
  }
}

SceneGltf Flattened(const SceneGltf& scene) {
  SceneGltf flat;
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    const SceneNode& node = scene.nodes[n];
    if (node.mesh < 0) continue;
    const glm::dmat4 world = NodeWorld(scene, static_cast<int>(n));
    SceneMesh mesh = scene.meshes[static_cast<std::size_t>(node.mesh)];
    for (glm::vec3& p : mesh.positions) p = glm::vec3(world * glm::dvec4(p, 1.0));
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
    for (glm::vec3& normal : mesh.normals) normal = glm::vec3(glm::normalize(normal_matrix * glm::dvec3(normal)));
    mesh.target_normals.clear();  // normal deltas do not move linearly
    for (auto& [name, deltas] : mesh.targets) {
      for (glm::vec3& d : deltas) d = glm::vec3(glm::dmat3(world) * glm::dvec3(d));
    }
    flat.meshes.push_back(mesh);
    flat.nodes.push_back({.name = node.name, .mesh = static_cast<int>(flat.meshes.size()) - 1});
    flat.roots.push_back(static_cast<int>(flat.nodes.size()) - 1);
  }
  return flat;
}

void AddEllipsoid(glm::vec3 centre, glm::vec3 radii, int rings, int segments, SceneMesh* mesh) {
  const auto first = static_cast<std::uint32_t>(mesh->positions.size());
  for (int r = 0; r <= rings; ++r) {
    const double polar = M_PI * (r + 0.5) / (rings + 1);  // from near +Z down to near -Z: no degenerate poles
    for (int s = 0; s < segments; ++s) {
      const double azimuth = 2.0 * M_PI * s / segments;
      const glm::dvec3 unit(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar));
      mesh->positions.push_back(centre + radii * glm::vec3(unit));
    }
  }
  auto at = [&](int r, int s) { return first + static_cast<std::uint32_t>(r * segments + (s % segments)); };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      // Outward: (down the rings) x (around the azimuth) points out of the surface.
      mesh->triangles.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      mesh->triangles.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
  }
}

void AddQuad(glm::vec3 corner, glm::vec3 u, glm::vec3 v, SceneMesh* mesh) {
  const auto first = static_cast<std::uint32_t>(mesh->positions.size());
  mesh->positions.insert(mesh->positions.end(), {corner, corner + u, corner + u + v, corner + v});
  mesh->triangles.push_back({first, first + 1, first + 2});
  mesh->triangles.push_back({first, first + 2, first + 3});
}

}  // namespace facerig::test
