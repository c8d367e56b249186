// glTF 2.0 reading and writing (.glb binary and .gltf text with an embedded
// buffer), through tinygltf.
//
// Writing: one mesh, one primitive per rig part on its own vertices (those its
// triangles use, so that a viewer such as three.js, which packs each
// primitive's targets into its own texture, holds each vertex's deltas once),
// one morph target per blend shape with POSITION (and NORMAL, when the rig has
// normal deltas) deltas stored as sparse accessors (all zero, without data,
// where a shape moves none of the part), target names in
// mesh.extras.targetNames (read by Blender and three.js), default weights 0.
// Each primitive's extras.facerig.vertices (an accessor) says which rig vertex
// each of its vertices is, so that reading joins the parts' vertices back
// into the rig's exactly. The node carries the scale to metres and, for Z-up
// rigs, the rotation to glTF's +Y up; units and up axis are also kept in
// mesh.extras.facerig.
// Reading accepts dense or sparse target accessors, primitives that share a
// vertex set or have their own, and triangle-list primitives.
// To add a rig's shapes to an artist's glTF and keep the rest of it (skin,
// nodes, materials, animations), see gltf_with_morph_targets.h.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// Throws IoError naming the path (and byte offset where known). External
// buffer files must be regular files inside the file's folder (no absolute
// path, no '..' or symbolic link leading out); texture files are not opened.
Rig ReadGltf(const std::filesystem::path& path);
// Same, from the bytes of a .glb or .gltf (the format from the extension of
// `path`, which names the file in errors and whose folder holds any external
// buffers).
Rig ParseGltf(std::span<const std::byte> bytes, const std::filesystem::path& path);

// The neutral geometry of the mesh ReadGltf reads, as a Mesh: its vertices and
// triangles in ReadGltf's order; per-corner UVs (TEXCOORD_0, with the rig's
// bottom-left origin) and normals when every primitive has them; one part per
// triangle-list primitive, named from extras.facerig.parts, else from the
// mesh's (or its node's) name (ReadGltf keeps "primitive<i>" there); every
// material of the document (name, baseColorFactor, alphaMode, alphaCutoff,
// doubleSided, and the uri of an external base-colour or normal image; images
// are neither opened nor decoded), plus a "default" one for primitives without
// a (valid) material when others have one. Morph targets are not read.
// Throws IoError as ReadGltf.
Mesh ReadGltfMesh(const std::filesystem::path& path);
Mesh ParseGltfMesh(std::span<const std::byte> bytes, const std::filesystem::path& path);
// ReadGltf and ReadGltfMesh from one parse; `mesh` may be null.
Rig ReadGltf(const std::filesystem::path& path, Mesh* mesh);

// Format from the extension (.glb or .gltf). Atomic (temporary file + rename).
// Shape and part names must be valid UTF-8 (IoError kWriteFailed otherwise).
void WriteGltf(const std::filesystem::path& path, const Rig& rig);
// Materials and images are written as the rig has them (images embedded in
// the buffer, never re-encoded); each part's primitive names its material.
// WriteGltf(path, rig, surface) writes RigWithSurface(rig, surface)
// (rig_surface.h); IoError(kWriteFailed) when `surface` does not fit the rig.
void WriteGltf(const std::filesystem::path& path, const Rig& rig, const Mesh& surface);

}  // namespace facerig
