// Building glTF data: buffer views, float accessors and the rig's shapes as
// sparse morph targets, for both glTF writers.
#include <algorithm>
#include <limits>
#include <numeric>
#include <utility>

#include <glm/common.hpp>

#include "gltf_internal.h"

namespace facerig::gltf_internal {

int BufferBuilder::AddView(const void* data, std::size_t size, int target) {
  while (static_cast<int>(model_->buffers.size()) <= buffer_) model_->buffers.emplace_back();
  std::vector<unsigned char>& bytes = model_->buffers[static_cast<std::size_t>(buffer_)].data;
  bytes.resize((bytes.size() + 3) & ~std::size_t{3}, 0);
  tinygltf::BufferView view;
  view.buffer = buffer_;
  view.byteOffset = bytes.size();
  view.byteLength = size;
  view.target = target;
  const auto* begin = static_cast<const unsigned char*>(data);
  bytes.insert(bytes.end(), begin, begin + size);
  model_->bufferViews.push_back(std::move(view));
  return static_cast<int>(model_->bufferViews.size()) - 1;
}

int AddAccessor(tinygltf::Model* model, tinygltf::Accessor accessor) {
  model->accessors.push_back(std::move(accessor));
  return static_cast<int>(model->accessors.size()) - 1;
}

tinygltf::Accessor FloatAccessor(int view, std::size_t count, int type) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.byteOffset = 0;
  accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  accessor.count = count;
  accessor.type = type;
  return accessor;
}

void SetMinMax(std::span<const glm::vec3> values, bool include_zero, tinygltf::Accessor* accessor) {
  glm::vec3 lo(std::numeric_limits<float>::max());
  glm::vec3 hi(std::numeric_limits<float>::lowest());
  for (const glm::vec3& v : values) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  // Elements a sparse accessor does not set are zero and count towards min/max.
  if (include_zero || values.empty()) {
    lo = glm::min(lo, glm::vec3(0.0f));
    hi = glm::max(hi, glm::vec3(0.0f));
  }
  accessor->minValues = {lo.x, lo.y, lo.z};
  accessor->maxValues = {hi.x, hi.y, hi.z};
}

tinygltf::Value StringArray(const std::vector<std::string>& strings) {
  tinygltf::Value::Array array;
  array.reserve(strings.size());
  for (const std::string& s : strings) array.emplace_back(s);
  return tinygltf::Value(std::move(array));
}

std::vector<std::map<std::string, int>> AddMorphTargets(tinygltf::Model* model, BufferBuilder* buffer,
                                                        const Rig& rig, std::uint32_t first_vertex,
                                                        std::uint32_t vertex_count, bool with_normals) {
  std::vector<std::uint32_t> vertices(vertex_count);
  std::iota(vertices.begin(), vertices.end(), first_vertex);
  return AddMorphTargets(model, buffer, rig, vertices, with_normals);
}

std::vector<std::map<std::string, int>> AddMorphTargets(tinygltf::Model* model, BufferBuilder* buffer,
                                                        const Rig& rig, std::span<const std::uint32_t> vertices,
                                                        bool with_normals) {
  std::vector<std::map<std::string, int>> targets;
  if (rig.shape_count() == 0) return targets;

  // Every shape's entries for these vertices live in three shared views, each
  // shape's sparse accessor pointing at its own range. Both the shape's
  // entries and `vertices` ascend, so one walk finds each entry's local index.
  std::vector<std::uint32_t> indices;
  std::vector<glm::vec3> positions, normals;
  std::vector<ShapeRange> ranges;
  const auto vertex_count = static_cast<std::uint32_t>(vertices.size());
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const BlendShapeView shape = rig.shape(s);
    const auto first = static_cast<std::uint32_t>(indices.size());
    auto local = vertices.begin();
    for (std::size_t e = 0; e < shape.vertex_indices.size(); ++e) {
      local = std::lower_bound(local, vertices.end(), shape.vertex_indices[e]);
      if (local == vertices.end()) break;
      if (*local != shape.vertex_indices[e]) continue;
      indices.push_back(static_cast<std::uint32_t>(local - vertices.begin()));
      positions.push_back(shape.position_deltas[e]);
      if (with_normals) normals.push_back(shape.normal_deltas[e]);
    }
    ranges.push_back({first, static_cast<std::uint32_t>(indices.size()) - first});
  }
  // No views when no shape moves these vertices (a view must not be empty).
  const bool any_entries = !indices.empty();
  const int index_view =
      any_entries ? buffer->AddView(indices.data(), indices.size() * sizeof(std::uint32_t), 0) : -1;
  const int position_view =
      any_entries ? buffer->AddView(positions.data(), positions.size() * sizeof(glm::vec3), 0) : -1;
  const int normal_view = any_entries && with_normals
                              ? buffer->AddView(normals.data(), normals.size() * sizeof(glm::vec3), 0)
                              : -1;

  auto sparse_accessor = [&](const ShapeRange& range, int values_view) {
    // No bufferView: elements default to zero and the sparse entries set the
    // rest. A shape without entries stays all zero, which needs no sparse
    // part at all (sparse.count must be >= 1).
    tinygltf::Accessor accessor = FloatAccessor(-1, vertex_count, TINYGLTF_TYPE_VEC3);
    if (range.count > 0) {
      accessor.sparse.isSparse = true;
      accessor.sparse.count = static_cast<int>(range.count);
      accessor.sparse.indices.bufferView = index_view;
      accessor.sparse.indices.byteOffset = static_cast<int>(range.offset * sizeof(std::uint32_t));
      accessor.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      accessor.sparse.values.bufferView = values_view;
      accessor.sparse.values.byteOffset = static_cast<int>(range.offset * sizeof(glm::vec3));
    }
    return accessor;
  };
  for (const ShapeRange& range : ranges) {
    std::map<std::string, int> target;
    tinygltf::Accessor position = sparse_accessor(range, position_view);
    SetMinMax(std::span<const glm::vec3>(positions).subspan(range.offset, range.count), range.count < vertex_count,
              &position);
    target["POSITION"] = AddAccessor(model, std::move(position));
    if (with_normals) target["NORMAL"] = AddAccessor(model, sparse_accessor(range, normal_view));
    targets.push_back(std::move(target));
  }
  return targets;
}

tinygltf::Value WithTargetNames(const tinygltf::Value& extras, const Rig& rig) {
  tinygltf::Value::Object object;
  if (extras.IsObject()) object = extras.Get<tinygltf::Value::Object>();
  if (rig.shape_count() == 0) {
    object.erase("targetNames");
  } else {
    std::vector<std::string> names;
    for (std::size_t s = 0; s < rig.shape_count(); ++s) names.emplace_back(rig.shape_name(s));
    object["targetNames"] = StringArray(names);
  }
  return tinygltf::Value(std::move(object));
}

}  // namespace facerig::gltf_internal
