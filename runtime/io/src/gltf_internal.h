// Pieces shared by the glTF reader and the two writers (a fresh document from
// a rig, and an artist's document with morph targets added): the container
// (parsing and atomic serialising), which mesh and vertices a rig comes from,
// and the morph target accessors. Used by facerig::runtime_io and by
// facerig::offline's writer into an artist's glTF; exposes tinygltf types, so
// it is no stable API.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <tiny_gltf.h>

#include "facerig/runtime/rig.h"

namespace facerig::gltf_internal {

enum class Format { kBinary, kText };

// .glb or .gltf (any case); throws IoError(kUnsupportedFormat) otherwise.
Format FormatFromExtension(const std::filesystem::path& path);

// What to do with image data while parsing.
enum class Images {
  kSkip,         // never decoded: a rig needs none
  kKeepEncoded,  // the encoded bytes of data-URI and external images kept in Image::image (see below)
};

// Reads and parses a .glb or .gltf (a .gltf that is really binary is read as
// such). With Images::kKeepEncoded, an image that is a data URI or an external
// file has its file bytes (PNG, JPEG...) in Image::image, not decoded pixels;
// images in bufferViews are left where they are. With Images::kSkip, external
// image files are not opened. External buffer and image files are read only
// inside the file's folder and only when regular (input_file.h); JSON nested
// deeper than kMaxJsonNesting is refused before tinygltf parses it. Throws
// IoError naming the path (and the field, e.g. "buffers[0].uri").
tinygltf::Model ParseModel(const std::filesystem::path& path, Format format, std::uint64_t* file_size,
                           Images images = Images::kSkip);
// Same, from the file's bytes: `path` names the file in errors, and external
// URIs resolve in its folder.
tinygltf::Model ParseModelBytes(std::span<const unsigned char> bytes, const std::filesystem::path& path,
                                Format format, Images images = Images::kSkip);

// Throws IoError(kUnsupportedFormat) naming the path when the file uses
// Draco or meshopt compression: its vertex data is not in plain accessors
// (a compressed POSITION accessor has no bufferView and would read as zeros).
void RefuseCompression(const tinygltf::Model& model, const std::string& path);

// Throws IoError(kWriteFailed) naming `path` and the name's index when a
// shape or part name of `rig` is not valid UTF-8, which glTF requires.
void RequireUtf8Names(const Rig& rig, const std::string& path);
// `text` with every byte that is not part of valid UTF-8 replaced by '?'.
std::string SanitizedUtf8(std::string_view text);

// Serialises `model` (every buffer embedded: buffer 0 as the BIN chunk of a
// .glb when it has no uri, the others as data URIs) and writes it atomically.
// Throws IoError(kWriteFailed) naming the path.
void WriteModel(const std::filesystem::path& path, Format format, const tinygltf::Model& model);

// The mesh a rig is read from: that of the first node, depth first, of the
// default scene that has one; else the first mesh. -1 when there is none.
int ChooseMesh(const tinygltf::Model& model);

// Vertices that triangle-list primitives share through one POSITION accessor.
// A rig's vertices are the blocks' vertices one after the other.
struct VertexBlock {
  int position_accessor = -1;
  const tinygltf::Primitive* primitive = nullptr;  // the first that uses it
  std::uint32_t first_vertex = 0;
  std::uint32_t vertex_count = 0;
};
struct MeshVertices {
  std::vector<std::size_t> triangle_primitives;  // indices into mesh.primitives, in order
  std::vector<VertexBlock> blocks;
  std::map<int, std::size_t> block_of_accessor;  // POSITION accessor -> index into blocks
  std::uint64_t vertex_count = 0;
};
// Throws IoError naming `path` when primitives share POSITION but not what
// goes with it, or when a count is absurd for a file of `file_size` bytes.
MeshVertices GroupMeshVertices(const tinygltf::Model& model, const tinygltf::Mesh& mesh, const std::string& path,
                               std::uint64_t file_size);

// The rig vertices each part's primitive carries in a fresh document, in
// ascending order: those its triangles use (a vertex two parts share is in
// both), and for the first part also the vertices no triangle uses. The
// primitive names them in extras.facerig.vertices (an accessor of rig vertex
// indices), which the reader welds back into the rig's vertices.
std::vector<std::vector<std::uint32_t>> PartVertexSets(const Rig& rig);

// For each vertex block, which rig vertex each of its vertices is, from
// extras.facerig.vertices of its primitive (facerig's own files, which write
// each part on its own vertices); empty when no primitive has one. Throws
// IoError naming `path` when only some have one or one is malformed.
std::vector<std::vector<std::uint32_t>> BlockRigVertices(const tinygltf::Model& model, const MeshVertices& vertices,
                                                         const std::string& path, std::uint64_t file_size);

// Appends data to buffer `buffer` of the model (created when missing), each
// view starting 4-byte aligned as glTF requires for float and uint32 accessors.
class BufferBuilder {
 public:
  explicit BufferBuilder(tinygltf::Model* model, int buffer = 0) : model_(model), buffer_(buffer) {}
  int AddView(const void* data, std::size_t size, int target);

 private:
  tinygltf::Model* model_;
  int buffer_;
};

int AddAccessor(tinygltf::Model* model, tinygltf::Accessor accessor);
tinygltf::Accessor FloatAccessor(int view, std::size_t count, int type);
// min/max of `values`, and of zero too when `include_zero`.
void SetMinMax(std::span<const glm::vec3> values, bool include_zero, tinygltf::Accessor* accessor);
tinygltf::Value StringArray(const std::vector<std::string>& strings);

// One morph target per shape of `rig` for primitives whose vertices are the
// rig's vertices [first_vertex, first_vertex + vertex_count): POSITION deltas,
// and NORMAL deltas when `with_normals` (the rig must have them), as sparse
// accessors without a bufferView (a shape that moves none of these vertices
// is all zero, without a sparse part). Returns each target's attributes.
std::vector<std::map<std::string, int>> AddMorphTargets(tinygltf::Model* model, BufferBuilder* buffer,
                                                        const Rig& rig, std::uint32_t first_vertex,
                                                        std::uint32_t vertex_count, bool with_normals);
// Same for primitives whose vertex i is the rig's vertex vertices[i]
// (ascending rig indices).
std::vector<std::map<std::string, int>> AddMorphTargets(tinygltf::Model* model, BufferBuilder* buffer,
                                                        const Rig& rig, std::span<const std::uint32_t> vertices,
                                                        bool with_normals);

// mesh.extras with "targetNames" set to the rig's shape names (none when it has no
// shapes); other members kept.
tinygltf::Value WithTargetNames(const tinygltf::Value& extras, const Rig& rig);

}  // namespace facerig::gltf_internal
