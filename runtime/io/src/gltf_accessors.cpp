#include "gltf_accessors.h"

#include <algorithm>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "gltf_components.h"

namespace facerig::gltf_internal {

const tinygltf::Accessor& GltfAccessors::GetAccessor(int index, const std::string& what) const {
  if (index < 0 || index >= static_cast<int>(model_.accessors.size())) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": accessor " + std::to_string(index) + " does not exist (" +
                                            std::to_string(model_.accessors.size()) + " accessors)");
  }
  return model_.accessors[index];
}

std::span<const std::byte> GltfAccessors::ViewBytes(int view_index, const std::string& what) const {
  const std::uint64_t length =
      view_index >= 0 && view_index < static_cast<int>(model_.bufferViews.size()) ? model_.bufferViews[view_index].byteLength : 0;
  const Elements bytes = ViewElements(view_index, 0, length, 1, false, what);
  // ViewElements checked that the view lies inside its buffer, so it fits in memory.
  return {reinterpret_cast<const std::byte*>(bytes.data), static_cast<std::size_t>(length)};
}

Elements GltfAccessors::ViewElements(int view_index, std::uint64_t byte_offset, std::uint64_t count,
                                  std::uint64_t element_size, bool allow_stride,
                                  const std::string& what) const {
  if (view_index < 0 || view_index >= static_cast<int>(model_.bufferViews.size())) {
    Fail(IoErrorKind::kIndexOutOfRange,
         what + ": bufferView " + std::to_string(view_index) + " does not exist");
  }
  const tinygltf::BufferView& view = model_.bufferViews[view_index];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size())) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": bufferView " + std::to_string(view_index) +
                                            " names buffer " + std::to_string(view.buffer) +
                                            ", which does not exist");
  }
  const std::vector<unsigned char>& buffer = model_.buffers[view.buffer].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
    Fail(IoErrorKind::kIndexOutOfRange,
         what + ": bufferView " + std::to_string(view_index) + " (bytes " + std::to_string(view.byteOffset) +
             " + " + std::to_string(view.byteLength) + ") lies outside its buffer of " +
             std::to_string(buffer.size()) + " bytes");
  }
  // Checked before anything is allocated from `count`: a count whose elements
  // could not fit in the whole buffer is absurd, not merely out of range.
  if (count > buffer.size() / element_size) {
    Fail(IoErrorKind::kAbsurdCount, what + ": " + std::to_string(count) + " elements of " +
                                        std::to_string(element_size) + " bytes cannot fit in a buffer of " +
                                        std::to_string(buffer.size()) + " bytes");
  }
  std::uint64_t stride = element_size;
  if (allow_stride && view.byteStride != 0) {
    if (view.byteStride < element_size || view.byteStride > 252) {
      Fail(IoErrorKind::kParse, what + ": byteStride " + std::to_string(view.byteStride) +
                                    " is invalid for elements of " + std::to_string(element_size) + " bytes");
    }
    stride = view.byteStride;
  }
  if (count > 0 && (byte_offset > view.byteLength ||
                    (count - 1) * stride + element_size > view.byteLength - byte_offset)) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": " + std::to_string(count) + " elements at offset " +
                                            std::to_string(byte_offset) + " run past the end of bufferView " +
                                            std::to_string(view_index) + " (" +
                                            std::to_string(view.byteLength) + " bytes)");
  }
  return {buffer.data() + view.byteOffset + byte_offset, static_cast<std::size_t>(stride)};
}

std::vector<std::uint32_t> GltfAccessors::ReadSparseIndices(const tinygltf::Accessor& accessor,
                                                         const std::string& what) const {
  const auto& sparse = accessor.sparse;
  if (sparse.count < 0) Fail(IoErrorKind::kParse, what + ": negative sparse count");
  if (static_cast<std::uint64_t>(sparse.count) > accessor.count) {
    Fail(IoErrorKind::kAbsurdCount, what + ": sparse count " + std::to_string(sparse.count) +
                                        " exceeds the accessor's count " + std::to_string(accessor.count));
  }
  if (!IsIndexType(sparse.indices.componentType)) {
    Fail(IoErrorKind::kParse, what + ": sparse indices must be UNSIGNED_BYTE, _SHORT or _INT");
  }
  if (sparse.indices.byteOffset < 0)
    Fail(IoErrorKind::kIndexOutOfRange, what + ": negative sparse byteOffset");
  const std::size_t index_size = ComponentSize(sparse.indices.componentType);
  const Elements elements =
      ViewElements(sparse.indices.bufferView, static_cast<std::uint64_t>(sparse.indices.byteOffset),
                   static_cast<std::uint64_t>(sparse.count), index_size, false, what + " sparse indices");
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(sparse.count));
  for (std::size_t i = 0; i < indices.size(); ++i) {
    indices[i] = LoadIndex(elements.data + i * elements.stride, sparse.indices.componentType);
    if (indices[i] >= accessor.count) {
      Fail(IoErrorKind::kIndexOutOfRange, what + ": sparse index " + std::to_string(indices[i]) +
                                              " >= count " + std::to_string(accessor.count));
    }
    if (i > 0 && indices[i] <= indices[i - 1]) {
      Fail(IoErrorKind::kParse, what + ": sparse indices are not strictly increasing");
    }
  }
  return indices;
}

// A float (or small normalized integer) accessor of `components` components
// and, when given, `expected_count` elements.
const tinygltf::Accessor& GltfAccessors::GetVectorAccessor(int accessor_index, int components,
                                                        std::optional<std::size_t> expected_count,
                                                        const std::string& what) const {
  const tinygltf::Accessor& accessor = GetAccessor(accessor_index, what);
  if (ComponentsOf(accessor.type) != components) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) + " is " +
                                  TypeName(accessor.type) + ", expected VEC" + std::to_string(components));
  }
  const int component_type = accessor.componentType;
  const std::size_t component_size = ComponentSize(component_type);
  if (component_type != TINYGLTF_COMPONENT_TYPE_FLOAT && (component_size == 0 || component_size > 2)) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) +
                                  " has an unsupported component type " + std::to_string(component_type));
  }
  if (expected_count && accessor.count != *expected_count) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) + " has " +
                                  std::to_string(accessor.count) + " elements, expected " +
                                  std::to_string(*expected_count));
  }
  // Elements without data (no bufferView) cost memory but no file bytes, so a
  // tiny file must not be able to ask for billions of them.
  if (accessor.bufferView < 0 && accessor.count > file_size_) {
    Fail(IoErrorKind::kAbsurdCount, what + ": accessor " + std::to_string(accessor_index) + " declares " +
                                        std::to_string(accessor.count) +
                                        " elements without data in a file of " + std::to_string(file_size_) +
                                        " bytes");
  }
  return accessor;
}

template <typename Vec>
VecData<Vec> GltfAccessors::ReadVectors(int accessor_index, std::optional<std::size_t> expected_count,
                                     bool keep_sparse, const std::string& what) const {
  constexpr int kComponents = static_cast<int>(Vec::length());
  const tinygltf::Accessor& accessor = GetVectorAccessor(accessor_index, kComponents, expected_count, what);
  const int component_type = accessor.componentType;
  const std::size_t component_size = ComponentSize(component_type);
  const std::size_t element_size = component_size * kComponents;
  auto load = [&](const unsigned char* p, std::size_t element) {
    Vec v;
    for (int c = 0; c < kComponents; ++c) {
      v[c] =
          LoadAsFloat(p + static_cast<std::size_t>(c) * component_size, component_type, accessor.normalized);
      if (!std::isfinite(v[c])) {
        Fail(IoErrorKind::kNonFinite, what + ": element " + std::to_string(element) + " of accessor " +
                                          std::to_string(accessor_index) + " is not finite");
      }
    }
    return v;
  };

  VecData<Vec> result;
  if (accessor.bufferView >= 0) {
    const Elements elements =
        ViewElements(accessor.bufferView, accessor.byteOffset, accessor.count, element_size, true, what);
    result.values.resize(accessor.count);
    for (std::size_t i = 0; i < accessor.count; ++i)
      result.values[i] = load(elements.data + i * elements.stride, i);
  }
  if (!accessor.sparse.isSparse) {
    if (accessor.bufferView < 0) result.values.assign(accessor.count, Vec(0.0f));
    return result;
  }
  const std::vector<std::uint32_t> indices = ReadSparseIndices(accessor, what);
  if (accessor.sparse.values.byteOffset < 0) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": negative sparse byteOffset");
  }
  const Elements values = ViewElements(accessor.sparse.values.bufferView,
                                       static_cast<std::uint64_t>(accessor.sparse.values.byteOffset),
                                       indices.size(), element_size, false, what + " sparse values");
  if (accessor.bufferView < 0 && keep_sparse) {
    result.sparse_only = true;
    result.values.resize(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i)
      result.values[i] = load(values.data + i * values.stride, indices[i]);
    result.sparse_indices = indices;
    return result;
  }
  if (accessor.bufferView < 0) result.values.assign(accessor.count, Vec(0.0f));
  for (std::size_t i = 0; i < indices.size(); ++i) {
    result.values[indices[i]] = load(values.data + i * values.stride, indices[i]);
  }
  return result;
}

std::vector<std::uint32_t> GltfAccessors::ReadIndices(const tinygltf::Primitive& primitive,
                                                   const VertexBlock& block, const std::string& what) const {
  std::vector<std::uint32_t> indices;
  if (primitive.indices < 0) {
    // Not indexed: consecutive vertices form the triangles.
    indices.resize(block.vertex_count);
    for (std::uint32_t i = 0; i < block.vertex_count; ++i) indices[i] = block.first_vertex + i;
  } else {
    indices = ReadIntegers(primitive.indices, GetAccessor(primitive.indices, what).count, block.vertex_count, what);
    for (std::uint32_t& index : indices) index += block.first_vertex;
  }
  if (indices.size() % 3 != 0) {
    Fail(IoErrorKind::kParse,
         what + ": " + std::to_string(indices.size()) + " indices is not a whole number of triangles");
  }
  return indices;
}

std::vector<std::uint32_t> GltfAccessors::ReadIntegers(int accessor_index, std::uint64_t expected_count,
                                                       std::uint64_t bound, const std::string& what) const {
  const tinygltf::Accessor& accessor = GetAccessor(accessor_index, what);
  if (accessor.type != TINYGLTF_TYPE_SCALAR || !IsIndexType(accessor.componentType)) {
    Fail(IoErrorKind::kParse, what + ": indices must be SCALAR UNSIGNED_BYTE, _SHORT or _INT");
  }
  if (accessor.bufferView < 0) Fail(IoErrorKind::kParse, what + ": the indices accessor has no bufferView");
  if (accessor.sparse.isSparse) Fail(IoErrorKind::kParse, what + ": sparse indices are not supported");
  if (accessor.count != expected_count) {
    Fail(IoErrorKind::kParse, what + ": " + std::to_string(accessor.count) + " elements, expected " +
                                  std::to_string(expected_count));
  }
  const Elements elements = ViewElements(accessor.bufferView, accessor.byteOffset, accessor.count,
                                         ComponentSize(accessor.componentType), false, what + " indices");
  std::vector<std::uint32_t> values(accessor.count);
  for (std::size_t i = 0; i < accessor.count; ++i) {
    values[i] = LoadIndex(elements.data + i * elements.stride, accessor.componentType);
    if (values[i] >= bound) {
      Fail(IoErrorKind::kIndexOutOfRange, what + ": index " + std::to_string(i) + " is " +
                                              std::to_string(values[i]) + ", but there are " +
                                              std::to_string(bound) + " vertices");
    }
  }
  return values;
}

template VecData<glm::vec2> GltfAccessors::ReadVectors<glm::vec2>(int, std::optional<std::size_t>, bool,
                                                                  const std::string&) const;
template VecData<glm::vec3> GltfAccessors::ReadVectors<glm::vec3>(int, std::optional<std::size_t>, bool,
                                                                  const std::string&) const;

}  // namespace facerig::gltf_internal
