// Import of a "folder of OBJs" template rig: one neutral OBJ plus one OBJ per
// expression with the same topology (e.g. ICT-FaceKit). Build-time only, so
// it lives in facerig::offline, not in the runtime's readers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/rig.h"

namespace facerig {

struct TemplateImportOptions {
  // Neutral file name inside the folder; empty: the first of
  // generic_neutral_mesh.obj, neutral.obj, base.obj that exists.
  std::string neutral_file;
  // Shape names (file stems). Empty: every .obj file that matches `glob`
  // except the neutral when `glob` is given, else the folder's
  // vertex_indices.json "expressions" list if present (ICT-FaceKit), else
  // every .obj file but the neutral.
  std::vector<std::string> shape_names;
  std::string glob;  // empty: "*.obj", after vertex_indices.json
  // Per-vertex deltas shorter than this fraction of the neutral's bounding-box
  // diagonal are dropped from the sparse shapes. 1e-6 is a few times the
  // rounding noise of OBJ files written with 6 significant digits; on
  // ICT-FaceKit it keeps 31% of the dense entries (exact zeros: 45%).
  float relative_drop_threshold = 1e-6f;
  // Also store normal deltas (expression normals minus neutral normals, both
  // area-weighted), for NormalMode::kBlendDeltas.
  bool with_normal_deltas = false;
  // kUnknown: guessed from the head's size (a head is ~0.25 m tall).
  Units units = Units::kUnknown;
  UpAxis up_axis = UpAxis::kY;
  // Where imports are kept between runs (template_cache.h); empty: none.
  // The tools use DefaultTemplateCacheFolder().
  std::filesystem::path cache_folder;
};

enum class TemplateCacheUse : std::uint8_t {
  kOff = 0,    // no cache_folder, or the folder's files could not be hashed
  kRead,       // the import was read from the cache
  kStored,     // imported, and kept in the cache
  kNotStored,  // imported; the cache could not be written (cache_problem)
};

struct TemplateImportReport {
  std::string neutral_path;
  float drop_threshold = 0.0f;  // absolute, in mesh units
  std::size_t kept_entries = 0;
  std::size_t dropped_entries = 0;  // non-zero deltas below the threshold
  float largest_dropped = 0.0f;     // longest dropped delta, in mesh units
  Units units = Units::kUnknown;
  bool units_guessed = false;
  std::size_t uv_seam_vertices = 0;
  TemplateCacheUse cache = TemplateCacheUse::kOff;
  std::string cache_problem;
};

// Throws IoError: kTopologyMismatch naming the offending expression file,
// kOpenFailed for a missing neutral or listed shape, and the OBJ reader's errors.
Rig ImportTemplateFolder(const std::filesystem::path& folder,
                         const TemplateImportOptions& options = {},
                         TemplateImportReport* report = nullptr);

// A directory is imported as a template folder; any other path is read by
// LoadRig (runtime_io) by its extension, an .obj with `options`' units and up
// axis. Throws IoError.
Rig LoadRigOrTemplateFolder(const std::filesystem::path& path, const TemplateImportOptions& options = {});

// Matches a file name against a glob with `*` and `?`.
bool GlobMatch(std::string_view pattern, std::string_view name);

// Guess of a head mesh's units from its bounding-box diagonal (in its units).
Units GuessHeadUnits(float bounding_diagonal);

}  // namespace facerig
