#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/io/gltf_with_morph_targets.h"

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "facerig/runtime/error.h"
#include "gltf_internal.h"

namespace facerig {
namespace {

using gltf_internal::AddAccessor;
using gltf_internal::AddMorphTargets;
using gltf_internal::BufferBuilder;
using gltf_internal::ChooseMesh;
using gltf_internal::FloatAccessor;
using gltf_internal::Format;
using gltf_internal::FormatFromExtension;
using gltf_internal::GroupMeshVertices;
using gltf_internal::Images;
using gltf_internal::MeshVertices;
using gltf_internal::ParseModel;
using gltf_internal::VertexBlock;
using gltf_internal::WithTargetNames;
using gltf_internal::RefuseCompression;
using gltf_internal::WriteModel;

using Targets = std::vector<std::map<std::string, int>>;

// A .glb has one BIN chunk: every buffer's bytes go into buffer 0, 4-byte
// aligned so that the views keep their alignment.
void MergeBuffers(tinygltf::Model* model) {
  if (model->buffers.empty()) return;
  std::vector<std::size_t> start(model->buffers.size(), 0);
  std::vector<unsigned char>& merged = model->buffers.front().data;
  for (std::size_t b = 1; b < model->buffers.size(); ++b) {
    merged.resize((merged.size() + 3) & ~std::size_t{3}, 0);
    start[b] = merged.size();
    merged.insert(merged.end(), model->buffers[b].data.begin(), model->buffers[b].data.end());
  }
  for (tinygltf::BufferView& view : model->bufferViews) {
    if (view.buffer <= 0 || view.buffer >= static_cast<int>(start.size())) continue;
    view.byteOffset += start[static_cast<std::size_t>(view.buffer)];
    view.buffer = 0;
  }
  model->buffers.resize(1);
  model->buffers.front().uri.clear();  // the BIN chunk
}

std::optional<std::string> MimeTypeOfFile(const std::string& uri) {
  const std::string extension =
      LowerAscii(uri.substr(uri.find_last_of('.') == std::string::npos ? uri.size() : uri.find_last_of('.')));
  if (extension == ".png") return "image/png";
  if (extension == ".jpg" || extension == ".jpeg") return "image/jpeg";
  if (extension == ".webp") return "image/webp";
  if (extension == ".ktx2") return "image/ktx2";
  return std::nullopt;
}

// Images that were data URIs (tinygltf keeps neither their uri nor their
// bytes) or external files (whose relative uri would break beside another
// output) move into a bufferView, byte for byte. Returns how many moved.
std::size_t EmbedImages(tinygltf::Model* model, BufferBuilder* buffer) {
  std::size_t embedded = 0;
  for (tinygltf::Image& image : model->images) {
    if (image.bufferView >= 0 || image.image.empty()) continue;
    std::vector<unsigned char> bytes = std::move(image.image);
    image.image.clear();
    if (!image.uri.empty()) {
      const std::optional<std::string> mime_type = MimeTypeOfFile(image.uri);
      if (!mime_type) continue;  // a type glTF cannot embed: the uri stays
      image.mimeType = *mime_type;
    }
    image.bufferView = buffer->AddView(bytes.data(), bytes.size(), 0);
    image.uri.clear();
    ++embedded;
  }
  return embedded;
}

// All-zero targets for primitives that share no vertices with the rig (lines,
// points, another vertex set): glTF wants the same number of targets on every
// primitive of a mesh.
Targets ZeroTargets(tinygltf::Model* model, std::size_t vertex_count, std::size_t shape_count) {
  tinygltf::Accessor zero = FloatAccessor(-1, vertex_count, TINYGLTF_TYPE_VEC3);
  zero.minValues = {0.0, 0.0, 0.0};
  zero.maxValues = {0.0, 0.0, 0.0};
  const int accessor = AddAccessor(model, std::move(zero));
  return Targets(shape_count, std::map<std::string, int>{{"POSITION", accessor}});
}

// "mesh 2 ('Head')", for messages.
std::string MeshLabel(int mesh_index, const std::string& mesh_name) {
  return "mesh " + std::to_string(mesh_index) + (mesh_name.empty() ? std::string() : " ('" + mesh_name + "')");
}

// An animation of the old targets' weights has one value per old target.
void RefuseAnimatedTargetWeights(const tinygltf::Model& model, int mesh_index, const std::string& mesh_label,
                                 const std::string& where) {
  for (const tinygltf::Animation& animation : model.animations) {
    for (const tinygltf::AnimationChannel& channel : animation.channels) {
      const int node = channel.target_node;
      if (channel.target_path == "weights" && node >= 0 && node < static_cast<int>(model.nodes.size()) &&
          model.nodes[static_cast<std::size_t>(node)].mesh == mesh_index) {
        throw IoError(IoErrorKind::kUnsupportedFormat, where,
                      "animation '" + animation.name + "' animates the morph target weights of " + mesh_label +
                          ", which the rig's shapes would replace; remove that animation first");
      }
    }
  }
}

// The rig's shapes as targets of each of the mesh's vertex blocks; in
// facerig's own files, each block's vertices are the rig vertices
// `rig_vertices` names (ascending), else the blocks follow one another.
std::vector<Targets> AddBlockTargets(tinygltf::Model* model, BufferBuilder* buffer, const Rig& rig,
                                     const MeshVertices& vertices,
                                     const std::vector<std::vector<std::uint32_t>>& rig_vertices,
                                     const std::string& where) {
  std::vector<Targets> block_targets;
  for (std::size_t b = 0; b < vertices.blocks.size(); ++b) {
    const VertexBlock& block = vertices.blocks[b];
    const bool with_normals = rig.has_normal_deltas() && block.primitive->attributes.count("NORMAL") > 0;
    if (rig_vertices.empty()) {
      block_targets.push_back(
          AddMorphTargets(model, buffer, rig, block.first_vertex, block.vertex_count, with_normals));
      continue;
    }
    const std::vector<std::uint32_t>& mine = rig_vertices[b];
    if (std::adjacent_find(mine.begin(), mine.end(), std::greater_equal<>()) != mine.end()) {
      throw IoError(IoErrorKind::kParse, where, "extras.facerig.vertices of a primitive is not ascending");
    }
    block_targets.push_back(AddMorphTargets(model, buffer, rig, mine, with_normals));
  }
  return block_targets;
}

// The rig vertices the mesh holds: as many as its blocks have, or in
// facerig's own files as many as extras.facerig.vertices name.
std::uint64_t RigVertexCount(const MeshVertices& vertices, const std::vector<std::vector<std::uint32_t>>& rig_vertices) {
  if (rig_vertices.empty()) return vertices.vertex_count;
  std::uint64_t count = 0;
  for (const std::vector<std::uint32_t>& block : rig_vertices) {
    for (std::uint32_t v : block) count = std::max<std::uint64_t>(count, v + std::uint64_t{1});
  }
  return count;
}

// Every primitive's targets: its vertex block's, all-zero ones for a
// primitive on other vertices, none without POSITION or without shapes.
void SetPrimitiveTargets(tinygltf::Model* model, tinygltf::Mesh* mesh, const MeshVertices& vertices,
                         const std::vector<Targets>& block_targets, std::size_t shape_count,
                         const std::string& mesh_label, const std::string& where) {
  std::map<std::size_t, Targets> zero_targets;  // by vertex count
  for (tinygltf::Primitive& primitive : mesh->primitives) {
    const auto position = primitive.attributes.find("POSITION");
    const auto block = position == primitive.attributes.end()
                           ? vertices.block_of_accessor.end()
                           : vertices.block_of_accessor.find(position->second);
    if (block != vertices.block_of_accessor.end()) {
      primitive.targets = block_targets[block->second];
      // A line or point primitive on the same vertices may lack their normals.
      if (primitive.attributes.count("NORMAL") == 0) {
        for (auto& target : primitive.targets) target.erase("NORMAL");
      }
      continue;
    }
    if (position == primitive.attributes.end() || shape_count == 0) {
      primitive.targets.clear();
      continue;
    }
    if (position->second < 0 || position->second >= static_cast<int>(model->accessors.size())) {
      throw IoError(IoErrorKind::kIndexOutOfRange, where,
                    mesh_label + ": a primitive's POSITION accessor " + std::to_string(position->second) +
                        " does not exist");
    }
    const std::size_t count = model->accessors[static_cast<std::size_t>(position->second)].count;
    auto [it, inserted] = zero_targets.try_emplace(count);
    if (inserted) it->second = ZeroTargets(model, count, shape_count);
    primitive.targets = it->second;
  }
}

}  // namespace

MorphTargetsWritten WriteGltfWithMorphTargets(const std::filesystem::path& source,
                                              const std::filesystem::path& output, const Rig& rig) {
  const Format source_format = FormatFromExtension(source);
  const Format output_format = FormatFromExtension(output);
  gltf_internal::RequireUtf8Names(rig, output.string());
  const std::string where = source.string();
  std::uint64_t file_size = 0;
  tinygltf::Model model = ParseModel(source, source_format, &file_size, Images::kKeepEncoded);
  RefuseCompression(model, where);

  const int mesh_index = ChooseMesh(model);
  if (mesh_index < 0) throw IoError(IoErrorKind::kEmpty, where, "the file has no mesh");
  tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(mesh_index)];
  const MeshVertices vertices = GroupMeshVertices(model, mesh, where, file_size);
  const std::vector<std::vector<std::uint32_t>> rig_vertices =
      gltf_internal::BlockRigVertices(model, vertices, where, file_size);
  MorphTargetsWritten written;
  written.mesh_name = mesh.name;
  const std::string mesh_label = MeshLabel(mesh_index, written.mesh_name);
  const std::uint64_t vertex_count = RigVertexCount(vertices, rig_vertices);
  if (vertex_count != rig.vertex_count()) {
    throw IoError(IoErrorKind::kTopologyMismatch, where,
                  mesh_label + " has " + std::to_string(vertex_count) + " vertices but the rig has " +
                      std::to_string(rig.vertex_count()) + ": the rig was not built on this mesh");
  }
  for (const tinygltf::Primitive& primitive : mesh.primitives) {
    written.replaced_targets = std::max(written.replaced_targets, primitive.targets.size());
  }
  RefuseAnimatedTargetWeights(model, mesh_index, mesh_label, where);

  if (output_format == Format::kBinary) MergeBuffers(&model);
  BufferBuilder buffer(&model, 0);
  written.embedded_images = EmbedImages(&model, &buffer);
  const std::vector<Targets> block_targets = AddBlockTargets(&model, &buffer, rig, vertices, rig_vertices, where);
  SetPrimitiveTargets(&model, &mesh, vertices, block_targets, rig.shape_count(), mesh_label, where);
  mesh.weights.assign(rig.shape_count(), 0.0);
  mesh.extras = WithTargetNames(mesh.extras, rig);
  // A node's own weights override the mesh's and must match its target count.
  for (tinygltf::Node& node : model.nodes) {
    if (node.mesh == mesh_index) node.weights.clear();
  }

  WriteModel(output, output_format, model);
  return written;
}

}  // namespace facerig
