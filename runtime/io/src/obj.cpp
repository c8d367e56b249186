#include "facerig/runtime/io/obj.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/files/input_file.h"
#include "obj_materials.h"
#include "text_lines.h"

namespace facerig {
namespace {

constexpr std::uint32_t kUnset = UINT32_MAX;

// Parses one OBJ file; keeps the line number for error messages.
class ObjParser {
 public:
  ObjParser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  Mesh Parse(ObjStats* stats) {
    ForEachLine(text_, [this](std::string_view line) {
      ++line_;
      ParseLine(line);
    });
    if (stats) {
      stats->polygon_count = polygon_count_;
      stats->mtl_files = std::move(mtl_files_);
    }
    return Finish();
  }

 private:
  [[noreturn]] void Fail(IoErrorKind kind, const std::string& message) const {
    throw IoError(kind, path_, message, line_);
  }

  static bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }

  static std::string_view Trim(std::string_view text) {
    while (!text.empty() && IsSpace(text.front())) text.remove_prefix(1);
    while (!text.empty() && IsSpace(text.back())) text.remove_suffix(1);
    return text;
  }

  // Next whitespace-separated token of `rest` (advancing it); empty at the end.
  static std::string_view NextToken(std::string_view& rest) {
    std::size_t begin = 0;
    while (begin < rest.size() && IsSpace(rest[begin])) ++begin;
    std::size_t end = begin;
    while (end < rest.size() && !IsSpace(rest[end])) ++end;
    const std::string_view token = rest.substr(begin, end - begin);
    rest.remove_prefix(end);
    return token;
  }

  float ParseFloat(std::string_view token) const {
    float value = 0.0f;
    const char* first = token.data();
    if (!token.empty() && token.front() == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), value);
    if (ec == std::errc::result_out_of_range) {
      Fail(IoErrorKind::kNonFinite, "number '" + std::string(token) + "' is out of float range");
    }
    if (ec != std::errc() || ptr != token.data() + token.size()) {
      Fail(IoErrorKind::kParse, "expected a number, found '" + std::string(token) + "'");
    }
    if (!std::isfinite(value)) {
      Fail(IoErrorKind::kNonFinite, "non-finite number '" + std::string(token) + "'");
    }
    return value;
  }

  template <int N>
  void ParseVector(std::string_view rest, float* out, const char* what) {
    for (int i = 0; i < N; ++i) {
      const std::string_view token = NextToken(rest);
      if (token.empty()) Fail(IoErrorKind::kParse, std::string(what) + " needs " + std::to_string(N) + " numbers");
      out[i] = ParseFloat(token);
    }
  }

  // Resolves a 1-based (or negative, relative) OBJ index into [0, count).
  std::uint32_t ResolveIndex(std::string_view token, std::size_t count, const char* what) const {
    long long value = 0;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || ptr != token.data() + token.size() || value == 0) {
      Fail(IoErrorKind::kParse, std::string("bad ") + what + " index '" + std::string(token) + "'");
    }
    const long long resolved = value > 0 ? value - 1 : static_cast<long long>(count) + value;
    if (resolved < 0 || resolved >= static_cast<long long>(count)) {
      Fail(IoErrorKind::kIndexOutOfRange, std::string(what) + " index " + std::string(token) +
                                              " is outside the " + std::to_string(count) +
                                              " defined so far");
    }
    return static_cast<std::uint32_t>(resolved);
  }

  struct Corner {
    std::uint32_t v, vt, vn;
  };

  Corner ParseCorner(std::string_view token) const {
    Corner corner{kUnset, kUnset, kUnset};
    const std::size_t slash1 = token.find('/');
    corner.v = ResolveIndex(token.substr(0, slash1), positions_.size(), "vertex");
    if (slash1 == std::string_view::npos) return corner;
    const std::string_view rest = token.substr(slash1 + 1);
    const std::size_t slash2 = rest.find('/');
    const std::string_view vt = rest.substr(0, slash2);
    if (!vt.empty()) corner.vt = ResolveIndex(vt, uvs_.size(), "texture coordinate");
    if (slash2 != std::string_view::npos) {
      const std::string_view vn = rest.substr(slash2 + 1);
      if (!vn.empty()) corner.vn = ResolveIndex(vn, normals_.size(), "normal");
    }
    return corner;
  }

  void ParseFace(std::string_view rest) {
    corners_.clear();
    for (std::string_view token = NextToken(rest); !token.empty(); token = NextToken(rest)) {
      corners_.push_back(ParseCorner(token));
    }
    if (corners_.size() < 3) Fail(IoErrorKind::kParse, "a face needs at least 3 vertices");
    ++polygon_count_;
    // Fan triangulation: exact for the convex polygons OBJ exporters write.
    for (std::size_t i = 1; i + 1 < corners_.size(); ++i) {
      triangles_.push_back({corners_[0].v, corners_[i].v, corners_[i + 1].v});
      for (const Corner* c : {&corners_[0], &corners_[i], &corners_[i + 1]}) corner_attributes_.push_back(*c);
      triangle_group_.push_back(current_group_);
      triangle_material_.push_back(current_material_);
    }
  }

  std::uint32_t Intern(std::vector<std::string>& names, std::string_view name) {
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (names[i] == name) return static_cast<std::uint32_t>(i);
    }
    names.emplace_back(name);
    return static_cast<std::uint32_t>(names.size() - 1);
  }

  void ParseLine(std::string_view line) {
    std::string_view rest = line;
    const std::string_view keyword = NextToken(rest);
    if (keyword.empty() || keyword.front() == '#') return;
    if (keyword == "v") {
      glm::vec3 p;
      ParseVector<3>(rest, &p.x, "a vertex");
      positions_.push_back(p);
    } else if (keyword == "vt") {
      glm::vec2 uv;
      ParseVector<2>(rest, &uv.x, "a texture coordinate");
      uvs_.push_back(uv);
    } else if (keyword == "vn") {
      glm::vec3 n;
      ParseVector<3>(rest, &n.x, "a normal");
      normals_.push_back(n);
    } else if (keyword == "f") {
      ParseFace(rest);
    } else if (keyword == "g" || keyword == "o") {
      const std::string_view name = NextToken(rest);
      current_group_ = Intern(group_names_, name.empty() ? "default" : name);
    } else if (keyword == "usemtl") {
      // The rest of the line, as MTL's newmtl: material names may contain spaces.
      const std::string_view name = Trim(rest);
      current_material_ = Intern(material_names_, name.empty() ? "default" : name);
      any_material_ = true;
    } else if (keyword == "mtllib") {
      for (std::string& name : SplitMtllibNames(rest)) {
        if (!name.empty()) mtl_files_.push_back(std::move(name));
      }
    }
    // Other statements (s, l, p, vp, curves) do not affect a triangle mesh.
  }

  // Corner attributes where any face gives them. A corner without one takes
  // the first value given for its vertex elsewhere (zero when none is), so a
  // face that omits `vt` does not make a seam.
  template <typename T>
  std::vector<T> CornerValues(const std::vector<T>& values, std::uint32_t Corner::*index) const {
    std::vector<T> corners;
    std::vector<std::uint32_t> first_of_vertex(positions_.size(), kUnset);
    bool any = false;
    for (std::size_t c = 0; c < corner_attributes_.size(); ++c) {
      const std::uint32_t given = corner_attributes_[c].*index;
      std::uint32_t& first = first_of_vertex[triangles_[c / 3][c % 3]];
      if (given != kUnset && first == kUnset) first = given;
      any = any || given != kUnset;
    }
    if (!any) return corners;
    corners.reserve(corner_attributes_.size());
    for (std::size_t c = 0; c < corner_attributes_.size(); ++c) {
      std::uint32_t chosen = corner_attributes_[c].*index;
      if (chosen == kUnset) chosen = first_of_vertex[triangles_[c / 3][c % 3]];
      corners.push_back(chosen == kUnset ? T(0.0f) : values[chosen]);
    }
    return corners;
  }

  // Per-triangle indices into `names`; unnamed triangles go to "default".
  static std::vector<std::uint32_t> NamedIndices(const std::vector<std::uint32_t>& keys,
                                                 std::vector<std::string>& names) {
    std::vector<std::uint32_t> indices(keys.begin(), keys.end());
    std::uint32_t unnamed = kUnset;
    for (std::uint32_t& index : indices) {
      if (index != kUnset) continue;
      if (unnamed == kUnset) {
        unnamed = static_cast<std::uint32_t>(names.size());
        names.emplace_back("default");
      }
      index = unnamed;
    }
    return indices;
  }

  Mesh Finish() {
    if (positions_.empty()) Fail(IoErrorKind::kEmpty, "no vertices");
    if (triangles_.empty()) Fail(IoErrorKind::kEmpty, "no faces");
    Mesh mesh;
    mesh.corner_uvs = CornerValues(uvs_, &Corner::vt);
    mesh.corner_normals = CornerValues(normals_, &Corner::vn);
    mesh.positions = std::move(positions_);
    mesh.triangles = std::move(triangles_);
    // Parts by material when the file names any, else by group.
    if (any_material_) {
      mesh.triangle_materials = NamedIndices(triangle_material_, material_names_);
      for (const std::string& name : material_names_) mesh.materials.push_back(Material{.name = name});
      mesh.triangle_parts = mesh.triangle_materials;
      mesh.part_names = material_names_;
    } else {
      mesh.triangle_parts = NamedIndices(triangle_group_, group_names_);
      mesh.part_names = std::move(group_names_);
    }
    return mesh;
  }

  std::string_view text_;
  const std::string& path_;
  std::int64_t line_ = 0;
  std::vector<glm::vec3> positions_;
  std::vector<glm::vec2> uvs_;
  std::vector<glm::vec3> normals_;
  std::vector<Triangle> triangles_;
  std::vector<std::uint32_t> triangle_group_;
  std::vector<std::uint32_t> triangle_material_;
  std::vector<std::string> group_names_;
  std::vector<std::string> material_names_;
  std::vector<std::string> mtl_files_;
  std::uint32_t current_group_ = kUnset;
  std::uint32_t current_material_ = kUnset;
  bool any_material_ = false;
  std::vector<Corner> corners_;            // of the face being parsed
  std::vector<Corner> corner_attributes_;  // 3 per triangle
  std::size_t polygon_count_ = 0;
};

// Appends `value` with std::to_chars: no locale, no temporary strings.
template <typename Number>
void AppendNumber(std::string& out, Number value) {
  char buffer[32];
  // Floats: the shortest representation that reads back to the same float.
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void AppendVertices(std::string& out, std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                    std::span<const glm::vec2> uvs) {
  out.reserve(out.size() + positions.size() * 40 + normals.size() * 40 + uvs.size() * 28);
  auto append_line = [&out](const char* keyword, const float* values, int count) {
    out += keyword;
    for (int i = 0; i < count; ++i) {
      out += ' ';
      AppendNumber(out, values[i]);
    }
    out += '\n';
  };
  for (const glm::vec3& p : positions) append_line("v", &p.x, 3);
  for (const glm::vec2& uv : uvs) append_line("vt", &uv.x, 2);
  for (const glm::vec3& n : normals) append_line("vn", &n.x, 3);
}

// Faces of each part after `usemtl <usemtl_names[part]>`; all faces when
// there are no parts.
void AppendFaces(std::string& out, std::span<const Triangle> triangles, std::span<const Part> parts,
                 std::span<const std::string> usemtl_names, bool with_normal, bool with_uv) {
  out.reserve(out.size() + triangles.size() * 40);
  auto append_corner = [&](std::uint32_t v) {
    char index[16];
    const std::size_t length = static_cast<std::size_t>(std::to_chars(index, index + sizeof(index), v + 1).ptr - index);
    out += ' ';
    out.append(index, length);
    if (with_uv || with_normal) {
      out += '/';
      if (with_uv) out.append(index, length);
      if (with_normal) {
        out += '/';
        out.append(index, length);
      }
    }
  };
  auto append_triangles = [&](std::size_t first, std::size_t count) {
    for (std::size_t t = first; t < first + count; ++t) {
      out += 'f';
      for (std::uint32_t v : triangles[t]) append_corner(v);
      out += '\n';
    }
  };
  if (parts.empty()) append_triangles(0, triangles.size());
  for (std::size_t p = 0; p < parts.size(); ++p) {
    out += "usemtl " + usemtl_names[p] + "\n";
    append_triangles(parts[p].first_triangle, parts[p].triangle_count);
  }
}

// Each part's material name; "default" (made unlike the materials' names) for
// a part without one.
std::vector<std::string> PartMaterialNames(const std::filesystem::path& path, std::span<const Part> parts,
                                           std::span<const std::string> material_names) {
  std::string fallback = "default";
  while (std::find(material_names.begin(), material_names.end(), fallback) != material_names.end()) fallback += '_';
  std::vector<std::string> names;
  for (const Part& part : parts) {
    if (part.material >= static_cast<std::int64_t>(material_names.size())) {
      throw IoError(IoErrorKind::kInvalidRig, path.string(),
                    "part '" + part.name + "' uses material " + std::to_string(part.material) + " of " +
                        std::to_string(material_names.size()));
    }
    names.push_back(part.material < 0 ? fallback : material_names[static_cast<std::size_t>(part.material)]);
  }
  return names;
}

// "<stem>.mtl" for the OBJ at `path`, with only characters safe in a file name.
std::string MtlFileName(const std::filesystem::path& path) {
  std::string stem = path.stem().string();
  for (char& c : stem) {
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
    if (!safe) c = '_';
  }
  stem.erase(0, stem.find_first_not_of('.'));
  return (stem.empty() ? std::string("materials") : stem) + ".mtl";
}

}  // namespace

Mesh ParseObj(std::string_view text, const std::string& path_for_errors, ObjStats* stats) {
  if (text.empty()) throw IoError(IoErrorKind::kEmpty, path_for_errors, "the file is empty");
  return ObjParser(text, path_for_errors).Parse(stats);
}

Mesh ReadObj(const std::filesystem::path& path, ObjStats* stats) {
  const std::string text = ReadInputText(path);
  ObjStats read;
  Mesh mesh = ParseObj(text, path.string(), &read);
  ReadObjMaterials(path, read.mtl_files, &mesh, &read.warnings);
  if (stats) *stats = std::move(read);
  return mesh;
}

ObjTopologyWriter::ObjTopologyWriter(std::span<const Triangle> triangles, std::span<const Part> parts,
                                     const MtlReference& mtl, bool with_normals, bool with_uvs,
                                     const std::string& path_for_errors)
    : header_("# written by facerig\n") {
  std::vector<std::string> usemtl_names;
  if (mtl.mtl_file.empty()) {
    for (const Part& part : parts) usemtl_names.push_back(part.name);
  } else {
    header_ += "mtllib " + mtl.mtl_file + "\n";
    usemtl_names = PartMaterialNames(path_for_errors, parts, mtl.material_names);
  }
  AppendFaces(faces_, triangles, parts, usemtl_names, with_normals, with_uvs);
}

void ObjTopologyWriter::Write(const std::filesystem::path& path, std::span<const glm::vec3> positions,
                              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs) const {
  std::string out;
  out.reserve(header_.size() + faces_.size() + positions.size() * 40 + normals.size() * 40 + uvs.size() * 28);
  out += header_;
  AppendVertices(out, positions, normals, uvs);
  out += faces_;
  WriteFileAtomically(path, out);
}

void WriteObj(const std::filesystem::path& path, std::span<const glm::vec3> positions,
              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs,
              std::span<const Triangle> triangles, std::span<const Part> parts) {
  WriteObj(path, positions, normals, uvs, triangles, parts, MtlReference{});
}

void WriteObj(const std::filesystem::path& path, std::span<const glm::vec3> positions,
              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs,
              std::span<const Triangle> triangles, std::span<const Part> parts, const MtlReference& mtl) {
  ObjTopologyWriter(triangles, parts, mtl, !normals.empty(), !uvs.empty(), path.string()).Write(path, positions, normals, uvs);
}

void WriteObj(const std::filesystem::path& path, const Rig& rig) {
  if (rig.materials().empty()) {
    WriteObj(path, rig.positions(), rig.normals(), rig.uvs(), rig.triangles(), rig.parts(), MtlReference{});
    return;
  }
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const MtlReference mtl = WriteMtl(folder, MtlFileName(path), rig.materials(), rig.images());
  WriteObj(path, rig, mtl);
}

void WriteObj(const std::filesystem::path& path, const Rig& rig, const MtlReference& mtl) {
  WriteObj(path, rig.positions(), rig.normals(), rig.uvs(), rig.triangles(), rig.parts(), mtl);
}

}  // namespace facerig
