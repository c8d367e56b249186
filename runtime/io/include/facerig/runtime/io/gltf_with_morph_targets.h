// Writing a rig's blend shapes into the artist's own glTF: the document the
// rig's mesh was read from, with morph targets added to that mesh and nothing
// else changed in meaning (nodes and their transforms, skins, joints and
// weights, other attributes, materials, textures, animations, extensions).
// Issue #6: a built rig must land on the target's own vertices, and a skinned
// character must stay skinned.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "facerig/runtime/rig.h"

namespace facerig {

struct MorphTargetsWritten {
  std::string mesh_name;              // the mesh that got the targets
  std::size_t replaced_targets = 0;   // morph targets the mesh had before, now replaced
  std::size_t embedded_images = 0;    // data-URI or external images moved into the output's buffer
};

// Reads `source` (.glb or .gltf), adds one morph target per shape of `rig` to
// the mesh ReadGltf reads from it (the first mesh of the default scene, depth
// first), on every primitive of that mesh, and writes the result to `output`
// (.glb or .gltf, either way round), atomically (temporary file + rename).
//
// The rig must have been built on that mesh's vertices: ReadGltf's vertex
// order (the triangle-list primitives' vertex sets one after the other) and
// its coordinates, which are the POSITION accessors' own values: the mesh's
// local space, before node transforms and skinning, which is where glTF
// applies morph targets. Targets carry POSITION deltas, and NORMAL deltas
// where the rig has them and the primitive has normals, as sparse accessors;
// mesh.extras.targetNames names them and mesh.weights is all zero.
//
// Morph targets the mesh already had are replaced (counted in the result; their
// accessors stay in the file, unused). Data is kept, not re-encoded: buffers
// are carried over (for a .glb output merged into its BIN chunk, for .gltf
// embedded as data URIs), and images that were data URIs or external files
// are embedded as they are (PNG, JPEG... bytes) so that the output stands alone.
//
// Throws IoError naming the file: the source unreadable or malformed, its mesh
// compressed (Draco, meshopt), its vertex count different from the rig's
// (kTopologyMismatch, both counts named), an animation of the old targets'
// weights (which cannot apply to the new targets), or the output unwritable.
MorphTargetsWritten WriteGltfWithMorphTargets(const std::filesystem::path& source,
                                              const std::filesystem::path& output, const Rig& rig);

}  // namespace facerig
