#include "support/test_meshes.h"

#include <cmath>
#include <mutex>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "facerig/runtime/error.h"
#if FACERIG_TEST_TEMPLATE_FOLDERS
#include "facerig/offline/io/template_folder.h"
#endif

namespace facerig::test {

Mesh MeshOf(std::span<const glm::vec3> positions, std::span<const Triangle> triangles) {
  return Mesh{.positions = {positions.begin(), positions.end()}, .triangles = {triangles.begin(), triangles.end()}};
}

void MakeUvSphere(int rings, int segments, const std::function<glm::vec3(double theta, double phi)>& point,
                  std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles) {
  positions.clear();
  triangles.clear();
  for (int r = 0; r <= rings; ++r) {
    const double theta = 3.14159265358979323846 * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * 3.14159265358979323846 * s / segments;
      positions.push_back(point(theta, phi));
    }
  }
  auto index = [&](int r, int s) { return static_cast<std::uint32_t>(r * segments + (s % segments)); };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      triangles.push_back({index(r, s), index(r + 1, s), index(r + 1, s + 1)});
      triangles.push_back({index(r, s), index(r + 1, s + 1), index(r, s + 1)});
    }
  }
}

RawRig MakeGridRawRig(int n, int shape_count, bool with_normal_deltas) {
  RawRig raw;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      raw.positions.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
      raw.uvs.emplace_back(static_cast<float>(x) / static_cast<float>(n - 1),
                           static_cast<float>(y) / static_cast<float>(n - 1));
    }
  }
  auto index = [n](int x, int y) { return static_cast<std::uint32_t>(y * n + x); };
  for (int y = 0; y + 1 < n; ++y) {
    for (int x = 0; x + 1 < n; ++x) {
      raw.triangles.push_back({index(x, y), index(x + 1, y), index(x + 1, y + 1)});
      raw.triangles.push_back({index(x, y), index(x + 1, y + 1), index(x, y + 1)});
    }
  }
  const auto half = static_cast<std::uint32_t>(raw.triangles.size() / 2);
  raw.parts.push_back({"left", 0, half});
  raw.parts.push_back({"right", half, static_cast<std::uint32_t>(raw.triangles.size()) - half});
  raw.units = Units::kCentimetres;
  for (int s = 0; s < shape_count; ++s) {
    RawBlendShape shape;
    shape.name = "shape" + std::to_string(s);
    for (std::uint32_t v = static_cast<std::uint32_t>(s); v < raw.positions.size();
         v += static_cast<std::uint32_t>(s + 2)) {
      shape.vertex_indices.push_back(v);
      const float t = static_cast<float>(v + 1) * 0.37f + static_cast<float>(s);
      shape.position_deltas.emplace_back(0.1f * std::sin(t), 0.05f * std::cos(t), 0.2f + 0.01f * static_cast<float>(s));
      if (with_normal_deltas) shape.normal_deltas.emplace_back(0.01f * std::cos(t), 0.02f, -0.01f);
    }
    raw.shapes.push_back(std::move(shape));
  }
  return raw;
}

Rig MakeGridRig(int n, int shape_count, bool with_normal_deltas) {
  std::string problem;
  auto rig = RigBuilder::Build(MakeGridRawRig(n, shape_count, with_normal_deltas), &problem);
  if (!rig) throw std::logic_error("grid rig invalid: " + problem);
  return std::move(*rig);
}

Rig MakeNamedGridRig(const std::vector<std::string>& names, int n) {
  RawRig raw = MakeGridRawRig(n, static_cast<int>(names.size()));
  for (std::size_t i = 0; i < names.size(); ++i) raw.shapes[i].name = names[i];
  std::string problem;
  auto rig = RigBuilder::Build(std::move(raw), &problem);
  if (!rig) throw std::logic_error("named grid rig invalid: " + problem);
  return std::move(*rig);
}

std::filesystem::path IctDir() { return FACERIG_ICT_DIR; }

const Rig& IctRig() {
  // ctest runs every test case in its own process, and importing 54 OBJs
  // takes ~0.5 s (~20 s under AddressSanitizer): the import goes through the
  // template cache (template_cache.h) in the tests' output folder, which
  // later processes read in ~0.1 s. Its key covers the importer's code, so a
  // rebuilt importer is always exercised.
  static std::once_flag once;
  static Rig rig;
  std::call_once(once, [] {
#if FACERIG_TEST_TEMPLATE_FOLDERS
    TemplateImportOptions options;
    options.cache_folder = OutputPath("template_cache");
    rig = ImportTemplateFolder(IctDir(), options);
#else
    throw std::runtime_error("the ICT-FaceKit rig is a template folder: reading it needs FACERIG_BUILD_OFFLINE");
#endif
  });
  return rig;
}

std::filesystem::path OutputPath(const std::string& file_name) {
  std::filesystem::path dir = FACERIG_TEST_OUTPUT_DIR;
  std::filesystem::create_directories(dir);
  return dir / file_name;
}

std::filesystem::path FreshOutputFolder(const std::string& name) {
  const std::filesystem::path folder = OutputPath(name);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

namespace {
bool Differ(std::string* difference, std::string text) {
  if (difference) *difference = std::move(text);
  return false;
}
bool Near(const glm::vec3& a, const glm::vec3& b, float tolerance) {
  return std::abs(a.x - b.x) <= tolerance && std::abs(a.y - b.y) <= tolerance &&
         std::abs(a.z - b.z) <= tolerance;
}
}  // namespace

bool RigsEqual(const Rig& a, const Rig& b, float tolerance, std::string* difference) {
  if (a.vertex_count() != b.vertex_count()) return Differ(difference, "vertex counts differ");
  if (a.triangle_count() != b.triangle_count()) return Differ(difference, "triangle counts differ");
  if (a.shape_count() != b.shape_count()) return Differ(difference, "shape counts differ");
  if (a.parts().size() != b.parts().size()) return Differ(difference, "part counts differ");
  if (a.units() != b.units() || a.up_axis() != b.up_axis()) return Differ(difference, "units or up axis differ");
  if (a.uvs().size() != b.uvs().size()) return Differ(difference, "UV presence differs");
  for (std::size_t t = 0; t < a.triangle_count(); ++t) {
    if (a.triangles()[t] != b.triangles()[t]) return Differ(difference, "triangle " + std::to_string(t) + " differs");
  }
  for (std::size_t i = 0; i < a.parts().size(); ++i) {
    const Part& pa = a.parts()[i];
    const Part& pb = b.parts()[i];
    if (pa.name != pb.name || pa.first_triangle != pb.first_triangle || pa.triangle_count != pb.triangle_count) {
      return Differ(difference, "part " + std::to_string(i) + " differs ('" + pa.name + "' vs '" + pb.name + "')");
    }
  }
  for (std::size_t v = 0; v < a.vertex_count(); ++v) {
    if (!Near(a.positions()[v], b.positions()[v], tolerance)) {
      return Differ(difference, "position " + std::to_string(v) + " differs");
    }
  }
  for (std::size_t s = 0; s < a.shape_count(); ++s) {
    const BlendShapeView sa = a.shape(s);
    const BlendShapeView sb = b.shape(s);
    if (sa.name != sb.name) return Differ(difference, "shape " + std::to_string(s) + " name differs");
    if (sa.vertex_indices.size() != sb.vertex_indices.size()) {
      return Differ(difference, "shape '" + std::string(sa.name) + "' entry counts differ: " +
                                    std::to_string(sa.vertex_indices.size()) + " vs " +
                                    std::to_string(sb.vertex_indices.size()));
    }
    for (std::size_t i = 0; i < sa.vertex_indices.size(); ++i) {
      if (sa.vertex_indices[i] != sb.vertex_indices[i] ||
          !Near(sa.position_deltas[i], sb.position_deltas[i], tolerance)) {
        return Differ(difference, "shape '" + std::string(sa.name) + "' entry " + std::to_string(i) + " differs");
      }
    }
  }
  return true;
}

std::vector<glm::vec3> DenseDeltas(const Rig& rig, std::size_t shape) {
  std::vector<glm::vec3> deltas(rig.vertex_count(), glm::vec3(0.0f));
  const BlendShapeView view = rig.shape(shape);
  for (std::size_t i = 0; i < view.vertex_indices.size(); ++i) deltas[view.vertex_indices[i]] = view.position_deltas[i];
  return deltas;
}

}  // namespace facerig::test
