// Validated reading of glTF accessors (dense, strided, sparse) into vectors
// and triangle indices, for the glTF reader. Private to facerig::runtime_io.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "facerig/runtime/error.h"
#include "gltf_internal.h"

namespace facerig::gltf_internal {

// One vec2/vec3 accessor as read. Dense: `values` has count elements. An
// accessor without a bufferView is zero except its sparse entries; when asked,
// those are kept as they are (`sparse_only`) instead of being expanded.
template <typename Vec>
struct VecData {
  std::vector<Vec> values;
  bool sparse_only = false;
  std::vector<std::uint32_t> sparse_indices;  // sparse_only: strictly increasing
};

// Where a run of elements lies: a validated pointer and the stride between them.
struct Elements {
  const unsigned char* data = nullptr;
  std::size_t stride = 0;
};

// Every offset, count and stride is checked against the buffers and the
// file's size before anything is allocated or read; errors name the file.
// A short-lived view: it refers to the reader's path and model.
class GltfAccessors {
 public:
  GltfAccessors(const std::string& path, const tinygltf::Model& model, std::uint64_t file_size)
      : path_(path), model_(model), file_size_(file_size) {}

  // Instantiated for glm::vec2 and glm::vec3.
  template <typename Vec>
  VecData<Vec> ReadVectors(int accessor_index, std::optional<std::size_t> expected_count, bool keep_sparse,
                           const std::string& what) const;
  std::vector<std::uint32_t> ReadIndices(const tinygltf::Primitive& primitive, const VertexBlock& block,
                                         const std::string& what) const;
  // A dense SCALAR accessor of unsigned integers (any index type), each below
  // `bound`; `expected_count` elements.
  std::vector<std::uint32_t> ReadIntegers(int accessor_index, std::uint64_t expected_count, std::uint64_t bound,
                                          const std::string& what) const;
  // The bytes of a whole bufferView (an embedded image).
  std::span<const std::byte> ViewBytes(int view_index, const std::string& what) const;

 private:
  [[noreturn]] void Fail(IoErrorKind kind, const std::string& message) const {
    throw IoError(kind, path_, message);
  }
  const tinygltf::Accessor& GetAccessor(int index, const std::string& what) const;
  Elements ViewElements(int view_index, std::uint64_t byte_offset, std::uint64_t count,
                        std::uint64_t element_size, bool allow_stride, const std::string& what) const;
  const tinygltf::Accessor& GetVectorAccessor(int accessor_index, int components,
                                              std::optional<std::size_t> expected_count,
                                              const std::string& what) const;
  std::vector<std::uint32_t> ReadSparseIndices(const tinygltf::Accessor& accessor,
                                               const std::string& what) const;

  const std::string& path_;
  const tinygltf::Model& model_;
  std::uint64_t file_size_;
};

}  // namespace facerig::gltf_internal
