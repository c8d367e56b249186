// A character as a DCC exporter writes it: several meshes, each with its own
// morph targets (names shared across meshes) and colour, under nested node
// transforms, optionally skinned to a joint hierarchy. Written with tinygltf
// (not with facerig's writer), so that it does not depend on the library
// under test.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "facerig/runtime/rig.h"

namespace facerig::test {

struct SceneMesh {
  std::string name;
  std::vector<glm::vec3> positions{};
  std::vector<Triangle> triangles{};
  std::vector<glm::vec3> normals{};  // none, or one per vertex
  std::vector<std::pair<std::string, std::vector<glm::vec3>>> targets{};  // name, one delta per vertex
  std::vector<std::vector<glm::vec3>> target_normals{};  // none, or normal deltas for every target
  glm::vec4 colour{1.0f};                                              // the material's base colour
  // Skinned meshes: up to four joints (indices into the skin's joints) and weights per vertex.
  std::vector<std::array<std::uint16_t, 4>> joints{};
  std::vector<glm::vec4> weights{};
};

struct SceneNode {
  std::string name;
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // w, x, y, z
  glm::dvec3 scale{1.0};
  int mesh = -1;
  int skin = -1;
  std::vector<int> children{};
};

struct SceneSkin {
  std::vector<int> joints;  // node indices
  // One per joint; empty: written without inverseBindMatrices (identity).
  std::vector<glm::mat4> inverse_binds;
};

struct SceneGltf {
  std::vector<SceneMesh> meshes;
  std::vector<SceneNode> nodes;
  std::vector<SceneSkin> skins;
  std::vector<int> roots;
};

// Writes `scene` as a .glb or .gltf (chosen by the extension).
void WriteSceneGltf(const std::filesystem::path& path, const SceneGltf& scene);

// Translation x rotation x scale of the node, and its parents' before it.
glm::dmat4 NodeWorld(const SceneGltf& scene, int node);

// The same scene as a viewer shows it, with every transform applied: each
// mesh's vertices and deltas moved by its node's world transform, and every
// node at the origin without rotation or scale. Not for skinned scenes.
SceneGltf Flattened(const SceneGltf& scene);

// A closed ellipsoid of `rings` x `segments` quads about `centre`, radii `radii`,
// wound counter-clockwise seen from outside.
void AddEllipsoid(glm::vec3 centre, glm::vec3 radii, int rings, int segments, SceneMesh* mesh);
// A rectangle from `corner` spanning `u` then `v`, counter-clockwise seen from u x v.
void AddQuad(glm::vec3 corner, glm::vec3 u, glm::vec3 v, SceneMesh* mesh);

}  // namespace facerig::test
