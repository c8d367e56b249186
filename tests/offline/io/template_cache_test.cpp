// The template cache (template_cache.h): a second import reads the entry and
// gives the same rig and report; a changed, added or removed file, other
// options or a damaged entry are never read as if nothing had changed.
#include "facerig/offline/io/template_cache.h"

#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include <catch2/catch.hpp>

#include "facerig/runtime/io/obj.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

// A 4x4 grid neutral and two expressions; an empty cache folder beside it.
struct CachedFolder {
  fs::path folder, cache;
  TemplateImportOptions options;
};

CachedFolder MakeCachedFolder(const std::string& name) {
  CachedFolder made{.folder = test::FreshOutputFolder(name) / "template", .cache = test::OutputPath(name) / "cache",
                    .options = {}};
  fs::create_directories(made.folder);
  const Rig rig = test::MakeGridRig(4, 0);
  WriteObj(made.folder / "neutral.obj", rig);
  std::vector<glm::vec3> moved(rig.positions().begin(), rig.positions().end());
  moved[5].z += 0.5f;
  WriteObj(made.folder / "smile.obj", moved, {}, {}, rig.triangles(), rig.parts());
  moved[6].x -= 0.25f;
  WriteObj(made.folder / "frown.obj", moved, {}, {}, rig.triangles(), rig.parts());
  made.options.cache_folder = made.cache;
  return made;
}

struct Imported {
  Rig rig;
  TemplateImportReport report;
};

Imported Import(const CachedFolder& at) {
  Imported imported;
  imported.rig = ImportTemplateFolder(at.folder, at.options, &imported.report);
  return imported;
}

void CheckSameRig(const Rig& a, const Rig& b) {
  REQUIRE(a.shape_count() == b.shape_count());
  CHECK(std::equal(a.positions().begin(), a.positions().end(), b.positions().begin()));
  CHECK(std::equal(a.normals().begin(), a.normals().end(), b.normals().begin()));
  CHECK(a.units() == b.units());
  for (std::size_t s = 0; s < a.shape_count(); ++s) {
    CHECK(a.shape_name(s) == b.shape_name(s));
    const BlendShapeView x = a.shape(s), y = b.shape(s);
    CHECK(std::equal(x.vertex_indices.begin(), x.vertex_indices.end(), y.vertex_indices.begin(),
                     y.vertex_indices.end()));
    CHECK(std::equal(x.position_deltas.begin(), x.position_deltas.end(), y.position_deltas.begin(),
                     y.position_deltas.end()));
  }
}

}  // namespace

TEST_CASE("Template cache: the second import is read from the cache, the same rig and report", "[template_cache]") {
  const CachedFolder at = MakeCachedFolder("template_cache_hit");
  const Imported first = Import(at);
  CHECK(first.report.cache == TemplateCacheUse::kStored);
  const Imported second = Import(at);
  CHECK(second.report.cache == TemplateCacheUse::kRead);
  CheckSameRig(first.rig, second.rig);
  CHECK(second.report.neutral_path == first.report.neutral_path);
  CHECK(second.report.kept_entries == first.report.kept_entries);
  CHECK(second.report.drop_threshold == first.report.drop_threshold);
  CHECK(second.report.units_guessed == first.report.units_guessed);

  // Without a cache folder nothing is read or written.
  TemplateImportOptions uncached;
  TemplateImportReport report;
  CheckSameRig(ImportTemplateFolder(at.folder, uncached, &report), first.rig);
  CHECK(report.cache == TemplateCacheUse::kOff);
}

TEST_CASE("Template cache: a changed, added or removed file or other options are imported again",
          "[template_cache]") {
  const CachedFolder at = MakeCachedFolder("template_cache_stale");
  const Imported before = Import(at);
  const Rig grid = test::MakeGridRig(4, 0);
  std::vector<glm::vec3> moved(grid.positions().begin(), grid.positions().end());

  // smile.obj moves another vertex: same size class of file, other bytes.
  moved[9].y += 0.125f;
  WriteObj(at.folder / "smile.obj", moved, {}, {}, grid.triangles(), grid.parts());
  const Imported changed = Import(at);
  CHECK(changed.report.cache == TemplateCacheUse::kStored);
  REQUIRE(changed.rig.shape_name(1) == "smile");
  CHECK(changed.rig.shape(1).vertex_indices[0] == 9u);
  CHECK(before.rig.shape(1).vertex_indices[0] == 5u);

  WriteObj(at.folder / "blink.obj", moved, {}, {}, grid.triangles(), grid.parts());
  const Imported added = Import(at);
  CHECK(added.report.cache == TemplateCacheUse::kStored);
  CHECK(added.rig.shape_count() == 3);

  fs::remove(at.folder / "blink.obj");
  const Imported removed = Import(at);
  CHECK(removed.report.cache == TemplateCacheUse::kRead);  // as before blink.obj came: that entry
  CHECK(removed.rig.shape_count() == 2);

  CachedFolder other_options = at;
  other_options.options.glob = "sm*.obj";
  const Imported by_glob = Import(other_options);
  CHECK(by_glob.report.cache == TemplateCacheUse::kStored);
  CHECK(by_glob.rig.shape_count() == 1);
}

TEST_CASE("Template cache: a damaged entry is imported again and replaced, and an unwritable cache only costs time",
          "[template_cache]") {
  const CachedFolder at = MakeCachedFolder("template_cache_damaged");
  const Imported first = Import(at);
  const std::optional<std::string> key = TemplateCacheKey(at.folder, at.options);
  REQUIRE(key.has_value());
  REQUIRE(fs::is_regular_file(at.cache / *key / "rig.frig"));
  fs::resize_file(at.cache / *key / "rig.frig", 100);  // cut short
  const Imported again = Import(at);
  CHECK(again.report.cache == TemplateCacheUse::kStored);
  CheckSameRig(again.rig, first.rig);
  CHECK(Import(at).report.cache == TemplateCacheUse::kRead);

  CachedFolder blocked = at;
  blocked.options.cache_folder = test::OutputPath("template_cache_damaged") / "a_file";
  std::ofstream(blocked.options.cache_folder) << "not a folder";
  const Imported uncached = Import(blocked);
  CHECK(uncached.report.cache == TemplateCacheUse::kNotStored);
  CHECK_FALSE(uncached.report.cache_problem.empty());
  CheckSameRig(uncached.rig, first.rig);
}

TEST_CASE("Template cache: its folder from FACERIG_CACHE_DIR, XDG_CACHE_HOME or HOME, and \"off\" turns it off",
          "[template_cache]") {
  const auto saved = [](const char* name) -> std::optional<std::string> {
    const char* value = std::getenv(name);
    return value ? std::optional<std::string>(value) : std::nullopt;
  };
  const std::optional<std::string> cache_dir = saved("FACERIG_CACHE_DIR"), xdg = saved("XDG_CACHE_HOME"),
                                   home = saved("HOME");
  setenv("FACERIG_CACHE_DIR", "/somewhere/cache", 1);
  CHECK(DefaultTemplateCacheFolder() == fs::path("/somewhere/cache"));
  setenv("FACERIG_CACHE_DIR", "off", 1);
  CHECK(DefaultTemplateCacheFolder().empty());
  unsetenv("FACERIG_CACHE_DIR");
  setenv("XDG_CACHE_HOME", "/xdg", 1);
  CHECK(DefaultTemplateCacheFolder() == fs::path("/xdg/facerig"));
  unsetenv("XDG_CACHE_HOME");
  setenv("HOME", "/home/someone", 1);
  CHECK(DefaultTemplateCacheFolder() == fs::path("/home/someone/.cache/facerig"));
  const auto restore = [](const char* name, const std::optional<std::string>& value) {
    if (value) {
      setenv(name, value->c_str(), 1);
    } else {
      unsetenv(name);
    }
  };
  restore("FACERIG_CACHE_DIR", cache_dir);
  restore("XDG_CACHE_HOME", xdg);
  restore("HOME", home);
}

}  // namespace facerig
