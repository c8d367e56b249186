#include "facerig/offline/transfer/displacement_transfer.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>

#include <Eigen/Dense>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "geometry/bounding_box.h"

namespace facerig {

namespace {

glm::vec3 Extent(std::span<const glm::vec3> positions, std::span<const std::uint32_t> subset) {
  return (subset.empty() ? BoxAround(positions) : BoxAround(positions, subset)).extent();
}

void CheckSize(std::size_t size, std::size_t expected, const std::string& mesh) {
  if (size != expected) {
    throw MeshInputError(mesh, "has " + std::to_string(size) + " vertices, expected " +
                                       std::to_string(expected));
  }
}

// --- binary helpers (explicit little-endian, whatever the host) ---
constexpr char kMagic[4] = {'F', 'D', 'M', '1'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint32_t kMaxNameLength = 4096;

std::uint32_t Fnv1a(std::span<const std::byte> bytes) {
  std::uint32_t hash = 2166136261u;
  for (std::byte b : bytes) {
    hash ^= static_cast<std::uint32_t>(b);
    hash *= 16777619u;
  }
  return hash;
}

void PutU32(std::vector<std::byte>& out, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) {
    out.push_back(static_cast<std::byte>((value >> shift) & 0xffu));
  }
}
void PutF32(std::vector<std::byte>& out, float value) { PutU32(out, std::bit_cast<std::uint32_t>(value)); }

class Reader {
 public:
  Reader(std::span<const std::byte> bytes, const std::string& path) : bytes_(bytes), path_(path) {}
  std::uint32_t U32(const char* what) {
    Need(4, what);
    std::uint32_t value = 0;
    for (int k = 0; k < 4; ++k) {
      value |= static_cast<std::uint32_t>(bytes_[offset_ + static_cast<std::size_t>(k)]) << (8 * k);
    }
    offset_ += 4;
    return value;
  }
  float F32(const char* what) {
    const std::size_t at = offset_;
    const float value = std::bit_cast<float>(U32(what));
    if (!std::isfinite(value)) {
      throw IoError(IoErrorKind::kNonFinite, path_, std::string(what) + " is not finite", 0,
                    static_cast<std::int64_t>(at));
    }
    return value;
  }
  std::string Text(std::size_t length, const char* what) {
    Need(length, what);
    std::string text(length, '\0');
    std::memcpy(text.data(), bytes_.data() + offset_, length);
    offset_ += length;
    return text;
  }
  void Need(std::size_t count, const char* what) const {
    if (bytes_.size() - offset_ < count) {
      throw IoError(IoErrorKind::kTruncated, path_, std::string("file ends inside ") + what, 0,
                    static_cast<std::int64_t>(offset_));
    }
  }
  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return bytes_.size() - offset_; }

 private:
  std::span<const std::byte> bytes_;
  const std::string& path_;
  std::size_t offset_ = 0;
};

}  // namespace

DisplacementMatrices ComputeDisplacementMatrices(std::span<const glm::vec3> neutral,
                                                 std::span<const std::vector<glm::vec3>> poses,
                                                 std::span<const std::string> names,
                                                 const DisplacementParams& params) {
  if (names.size() != poses.size()) {
    throw MeshInputError("pose names", std::to_string(names.size()) + " names for " +
                                               std::to_string(poses.size()) + " poses");
  }
  DisplacementMatrices matrices;
  matrices.vertex_count = neutral.size();
  matrices.base_extent = Extent(neutral, {});
  matrices.names.assign(names.begin(), names.end());
  const std::size_t n = neutral.size();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    CheckSize(poses[k].size(), n, "pose '" + names[k] + "'");
    std::vector<glm::vec3> displacement(n);
    SimilarityTransform align;
    if (params.rigid_align && n >= 3) {
      std::vector<std::uint32_t> subset = params.alignment_vertices;
      if (subset.empty()) {
        // The half of the vertices this pose moves least.
        std::vector<float> motion(n);
        for (std::size_t v = 0; v < n; ++v) motion[v] = glm::length(poses[k][v] - neutral[v]);
        subset.resize(n);
        std::iota(subset.begin(), subset.end(), 0u);
        const auto half = subset.begin() + static_cast<std::ptrdiff_t>(std::max<std::size_t>(3, n / 2));
        std::nth_element(subset.begin(), half, subset.end(),
                         [&motion](std::uint32_t a, std::uint32_t b) { return motion[a] < motion[b]; });
        subset.erase(half, subset.end());
      }
      align = FitRigid(poses[k], neutral, subset);
    }
    for (std::size_t v = 0; v < n; ++v) displacement[v] = align.Apply(poses[k][v]) - neutral[v];
    matrices.displacements.push_back(std::move(displacement));
  }
  return matrices;
}

DisplacementMatrices ComputeDisplacementMatrices(const Rig& rig) {
  DisplacementMatrices matrices;
  const std::span<const glm::vec3> neutral = rig.positions();
  matrices.vertex_count = neutral.size();
  matrices.base_extent = Extent(neutral, {});
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    matrices.names.emplace_back(rig.shape_name(s));
    std::vector<glm::vec3> displacement(neutral.size(), glm::vec3(0.0f));
    const BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      displacement[shape.vertex_indices[i]] = shape.position_deltas[i];
    }
    matrices.displacements.push_back(std::move(displacement));
  }
  return matrices;
}

DisplacementTransferResult TransferDisplacements(const DisplacementMatrices& matrices,
                                                 std::span<const glm::vec3> model_neutral,
                                                 const DisplacementTransferParams& params) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = matrices.vertex_count;
  CheckSize(model_neutral.size(), n, "model neutral");
  for (std::size_t k = 0; k < matrices.displacements.size(); ++k) {
    CheckSize(matrices.displacements[k].size(), n, "displacement matrix '" + matrices.names[k] + "'");
  }
  DisplacementTransferResult result;
  std::vector<glm::vec3> model_in_base(model_neutral.begin(), model_neutral.end());
  if (!params.base_neutral.empty()) CheckSize(params.base_neutral.size(), n, "base neutral");
  if (!params.base_neutral.empty() && params.align_model) {
    result.model_to_base = FitRigid(model_neutral, params.base_neutral, {}, &result.model_to_base_rms);
    for (glm::vec3& p : model_in_base) p = result.model_to_base.Apply(p);
  }
  const std::span<const std::uint32_t> box_subset = params.bounding_box_vertices;
  for (std::uint32_t v : box_subset) {
    if (v >= n) {
      throw MeshInputError("bounding box vertices", "vertex " + std::to_string(v) + " out of range");
    }
  }
  if (params.normalize_by_bounding_box && !box_subset.empty() && params.base_neutral.empty()) {
    throw MeshInputError("base neutral", "needed to compare bounding boxes over a vertex subset");
  }
  if (params.normalize_by_bounding_box) {
    // The base's box over the same subset when the base neutral is known.
    const glm::vec3 base_extent =
        box_subset.empty() ? matrices.base_extent : Extent(params.base_neutral, box_subset);
    const glm::vec3 model_extent = Extent(model_in_base, box_subset);
    for (int axis = 0; axis < 3; ++axis) {
      if (!(model_extent[axis] > 0.0f) || !(base_extent[axis] > 0.0f)) {
        throw MeshInputError("model neutral", "empty bounding box on an axis");
      }
      // Mattos et al.'s normalisation as printed multiplies by X_base / X_model, which
      // shrinks the displacements on a bigger face; they must scale WITH the
      // face, so the ratio used here is X_model / X_base.
      result.scale[axis] = model_extent[axis] / base_extent[axis];
    }
  }
  const SimilarityTransform base_to_model = result.model_to_base.Inverse();
  result.poses.resize(matrices.displacements.size());
  for (std::size_t k = 0; k < matrices.displacements.size(); ++k) {
    std::vector<glm::vec3>& pose = result.poses[k];
    pose.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
      const glm::vec3 d = matrices.displacements[k][v] * result.scale;
      pose[v] = model_neutral[v] + base_to_model.ApplyToDirection(d);
    }
  }
  result.seconds = SecondsSince(start);
  return result;
}

std::vector<glm::vec3> CombinePoses(const DisplacementMatrices& matrices,
                                    std::span<const float> weights) {
  if (weights.size() != matrices.displacements.size()) {
    throw MeshInputError("weights", std::to_string(weights.size()) + " weights for " +
                                            std::to_string(matrices.displacements.size()) + " poses");
  }
  std::vector<glm::vec3> combined(matrices.vertex_count, glm::vec3(0.0f));
  for (std::size_t k = 0; k < weights.size(); ++k) {
    if (weights[k] == 0.0f) continue;
    CheckSize(matrices.displacements[k].size(), matrices.vertex_count,
              "displacement matrix '" + matrices.names[k] + "'");
    for (std::size_t v = 0; v < combined.size(); ++v) {
      combined[v] += weights[k] * matrices.displacements[k][v];
    }
  }
  return combined;
}

void WriteDisplacementMatrices(const std::filesystem::path& path,
                               const DisplacementMatrices& matrices) {
  const std::string where = path.string();
  if (matrices.names.size() != matrices.displacements.size()) {
    throw IoError(IoErrorKind::kWriteFailed, where, "names and matrices differ in count");
  }
  std::vector<std::byte> out;
  out.reserve(32 + matrices.displacements.size() * (matrices.vertex_count * 12 + 64));
  for (char c : kMagic) out.push_back(static_cast<std::byte>(c));
  PutU32(out, kVersion);
  PutU32(out, static_cast<std::uint32_t>(matrices.vertex_count));
  PutU32(out, static_cast<std::uint32_t>(matrices.displacements.size()));
  for (int axis = 0; axis < 3; ++axis) PutF32(out, matrices.base_extent[axis]);
  for (std::size_t k = 0; k < matrices.displacements.size(); ++k) {
    const std::string& name = matrices.names[k];
    if (name.size() > kMaxNameLength) {
      throw IoError(IoErrorKind::kWriteFailed, where, "pose name longer than 4096 bytes");
    }
    if (matrices.displacements[k].size() != matrices.vertex_count) {
      throw IoError(IoErrorKind::kWriteFailed, where, "pose '" + name + "' has the wrong vertex count");
    }
    PutU32(out, static_cast<std::uint32_t>(name.size()));
    for (char c : name) out.push_back(static_cast<std::byte>(c));
    for (const glm::vec3& d : matrices.displacements[k]) {
      if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) {
        throw IoError(IoErrorKind::kWriteFailed, where, "pose '" + name + "' has a non-finite displacement");
      }
      PutF32(out, d.x);
      PutF32(out, d.y);
      PutF32(out, d.z);
    }
  }
  PutU32(out, Fnv1a(out));
  WriteFileAtomically(path, out);
}

DisplacementMatrices ReadDisplacementMatrices(const std::filesystem::path& path) {
  const std::string where = path.string();
  const std::vector<std::byte> bytes = ReadFileBytes(path);
  if (bytes.empty()) throw IoError(IoErrorKind::kEmpty, where, "empty file");
  Reader reader(bytes, where);
  if (reader.Text(4, "magic") != std::string(kMagic, 4)) {
    throw IoError(IoErrorKind::kBadMagic, where, "not a displacement-matrix file (magic FDM1)", 0, 0);
  }
  const std::uint32_t version = reader.U32("version");
  if (version != kVersion) {
    throw IoError(IoErrorKind::kUnsupportedVersion, where,
                  "version " + std::to_string(version) + " (this build reads 1)", 0, 4);
  }
  DisplacementMatrices matrices;
  const std::uint32_t vertex_count = reader.U32("vertex count");
  const std::uint32_t pose_count = reader.U32("pose count");
  for (int axis = 0; axis < 3; ++axis) matrices.base_extent[axis] = reader.F32("base extent");
  // Every pose needs at least 4 + 12 N bytes: refuse counts far beyond what the
  // file holds before allocating (a file merely cut short reads as kTruncated).
  const std::uint64_t per_pose = 4 + 12 * static_cast<std::uint64_t>(vertex_count);
  if (static_cast<std::uint64_t>(pose_count) * per_pose > 2 * static_cast<std::uint64_t>(reader.remaining()) + 64) {
    throw IoError(IoErrorKind::kAbsurdCount, where,
                  std::to_string(pose_count) + " poses of " + std::to_string(vertex_count) +
                      " vertices cannot fit in the file");
  }
  matrices.vertex_count = vertex_count;
  for (std::uint32_t k = 0; k < pose_count; ++k) {
    const std::uint32_t length = reader.U32("name length");
    if (length > kMaxNameLength) {
      throw IoError(IoErrorKind::kAbsurdCount, where, "pose name of " + std::to_string(length) + " bytes",
                    0, static_cast<std::int64_t>(reader.offset() - 4));
    }
    matrices.names.push_back(reader.Text(length, "pose name"));
    reader.Need(12 * static_cast<std::size_t>(vertex_count), "displacements");
    std::vector<glm::vec3> displacement(vertex_count);
    for (glm::vec3& d : displacement) {
      d.x = reader.F32("displacement");
      d.y = reader.F32("displacement");
      d.z = reader.F32("displacement");
    }
    matrices.displacements.push_back(std::move(displacement));
  }
  const std::size_t checked = reader.offset();
  const std::uint32_t stored = reader.U32("checksum");
  if (reader.remaining() != 0) {
    throw IoError(IoErrorKind::kParse, where, "trailing bytes after the checksum", 0,
                  static_cast<std::int64_t>(reader.offset()));
  }
  if (Fnv1a(std::span(bytes).first(checked)) != stored) {
    throw IoError(IoErrorKind::kChecksumMismatch, where, "FNV-1a checksum differs from the data");
  }
  return matrices;
}

}  // namespace facerig
