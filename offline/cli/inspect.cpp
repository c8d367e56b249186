// `facerig inspect`, `facerig convert` and `facerig default-head`: reading,
// converting and generating rigs.
#include "cli/commands.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "cli/common.h"
#include "cli/names.h"
#include "cli/obj_folder.h"
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/rig_warnings.h"

namespace facerig::cli {
namespace {

struct RigFileOptions {
  std::vector<std::string> paths;  // inspect: FILE|DIR; convert: IN OUT
  TemplateImportOptions folder;
  std::string report;  // --json
  StandardShapesOptions naming;  // convert
  bool neutral_only = false;     // convert --neutral-only
};

struct DefaultHeadOptions {
  std::string out_dir, preview_dir, report;
  int preview_size = 256;
  StandardShapesOptions naming;
};

// The options for template folders and .obj input.
void AddFolderOptions(CLI::App& app, TemplateImportOptions& folder) {
  AddUnitsOption(app, folder.units, "units of the input (default: guessed from the head size)");
  AddUpAxisOption(app, folder.up_axis, "up axis of the input (default y)");
  app.add_option("--neutral", folder.neutral_file, "neutral OBJ inside the folder");
  AddCommaListOption(app, "--shapes", folder.shape_names,
                     "expression names a,b,c (default: --glob, else vertex_indices.json, else every *.obj)");
  app.add_option("--glob", folder.glob, "expression files, e.g. 'mouth*.obj' (used over vertex_indices.json when given)");
  app.add_option("--drop-threshold", folder.relative_drop_threshold,
                 "drop deltas shorter than REL x bounding diagonal (default 1e-6)")
      ->check(InRange(0.0f, 1.0f));
  app.footer("Formats by extension: a template folder of OBJs, .obj (neutral only), .glb, .gltf, .frig.");
}

Rig Load(const std::string& path, const TemplateImportOptions& folder) {
  if (std::filesystem::is_directory(path)) {
    TemplateImportReport report;
    Rig rig = ImportTemplateFolder(path, folder, &report);
    std::printf("imported %s: neutral %s, units %s%s, drop threshold %.3g (%zu small deltas dropped, "
                "longest %.3g), %zu vertices with several UVs (first kept)\n",
                path.c_str(), report.neutral_path.c_str(), ToString(report.units),
                report.units_guessed ? " (guessed from size)" : "", report.drop_threshold,
                report.dropped_entries, report.largest_dropped, report.uv_seam_vertices);
    return rig;
  }
  return LoadRigOrTemplateFolder(path, folder);
}

void Inspect(const Rig& rig) {
  std::printf("vertices %zu, triangles %zu, UVs %s, units %s, up %s, normal deltas %s\n",
              rig.vertex_count(), rig.triangle_count(), rig.uvs().empty() ? "no" : "yes",
              ToString(rig.units()), ToString(rig.up_axis()),
              rig.has_normal_deltas() ? "yes" : "no");
  std::printf("bounding diagonal %.4g %s\n", static_cast<double>(rig.bounding_diagonal()),
              ToString(rig.units()));
  std::printf("\nparts (%zu):\n  %-24s %18s %18s\n", rig.parts().size(), "name", "triangles",
              "vertex span");
  for (const Part& part : rig.parts()) {
    std::printf("  %-24s %8u +%-9u %8u +%-9u\n", part.name.c_str(), part.first_triangle,
                part.triangle_count, part.first_vertex, part.vertex_count);
  }
  std::printf("\nshapes (%zu):\n  %-24s %9s %9s %12s\n", rig.shape_count(), "name", "vertices",
              "% of mesh", "max delta");
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const BlendShapeView shape = rig.shape(s);
    float max_delta = 0.0f;
    for (const glm::vec3& d : shape.position_deltas) max_delta = std::max(max_delta, glm::length(d));
    std::printf("  %-24.*s %9zu %8.2f%% %12.4g\n", static_cast<int>(shape.name.size()),
                shape.name.data(), shape.vertex_indices.size(),
                100.0 * static_cast<double>(shape.vertex_indices.size()) /
                    static_cast<double>(rig.vertex_count()),
                static_cast<double>(max_delta));
  }
  const double dense = static_cast<double>(rig.shape_count() * rig.vertex_count());
  const std::size_t entry_bytes = rig.has_normal_deltas() ? 28 : 16;
  std::printf("\nsparsity: %zu entries = %.2f%% of dense (%zu shapes x %zu vertices); "
              "shape data %.2f MB sparse vs %.2f MB dense\n",
              rig.total_shape_entries(),
              dense > 0 ? 100.0 * static_cast<double>(rig.total_shape_entries()) / dense : 0.0,
              rig.shape_count(), rig.vertex_count(),
              static_cast<double>(rig.total_shape_entries() * entry_bytes) / 1e6,
              dense * static_cast<double>(entry_bytes - 4) / 1e6);
}

// inspect --json: the counts and the shape names.
nlohmann::json InspectResult(const Rig& rig) {
  nlohmann::json shapes = nlohmann::json::array();
  for (std::size_t s = 0; s < rig.shape_count(); ++s) shapes.push_back(std::string(rig.shape_name(s)));
  return {{"vertices", rig.vertex_count()},
          {"triangles", rig.triangle_count()},
          {"units", ToString(rig.units())},
          {"parts", rig.parts().size()},
          {"materials", rig.materials().size()},
          {"images", rig.images().size()},
          {"shape_entries", rig.total_shape_entries()},
          {"shapes", shapes},
          {"arkit_match", ShapeMatchesJson(rig)}};
}

int RunInspect(const RigFileOptions& options) {
  try {
    CheckWritable({options.report});
    const auto start = std::chrono::steady_clock::now();
    const Rig rig = Load(options.paths[0], options.folder);
    const double load_seconds = SecondsSince(start);
    std::printf("%s (loaded in %.3f s)\n", options.paths[0].c_str(), load_seconds);
    Inspect(rig);
    PrintShapeMatches(rig);
    CommandReport report{"inspect", {{"rig", options.paths[0]}}, {}, SpeechAndBlinkWarnings(rig)};
    std::fflush(stdout);
    for (const RigWarning& warning : report.warnings) {
      std::fprintf(stderr, "facerig: warning: %s\n", warning.message.c_str());
    }
    if (!options.report.empty()) {
      report.timings = {{"load", load_seconds}, {"total", SecondsSince(start)}};
      report.result = InspectResult(rig);
      WriteCommandReport(options.report, report);
    }
    return 0;
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

// convert's OUT is a folder of OBJs (neutral.obj and one OBJ per shape, the
// form facerig reads as a template folder) when it ends in '/' or is a folder.
bool IsFolderOutput(const std::string& output) {
  return output.ends_with('/') || std::filesystem::is_directory(output);
}

// The rig without its shapes (convert --neutral-only).
Rig NeutralOnly(const Rig& rig) {
  RawRig raw = RigBuilder::ToRaw(rig);
  raw.shapes.clear();
  std::string problem;
  std::optional<Rig> neutral = RigBuilder::Build(std::move(raw), &problem);
  if (!neutral) throw std::runtime_error("cannot drop the shapes: " + problem);
  return std::move(*neutral);
}

// What convert wrote, for its last line: counts that are true of the file.
std::string ConvertSummary(const std::string& output, const Rig& rig, bool folder, std::size_t dropped,
                           std::uintmax_t bytes) {
  char line[512];
  if (folder) {
    std::snprintf(line, sizeof line, "wrote %s (neutral.obj and %zu shape OBJs, %zu vertices each)", output.c_str(),
                  rig.shape_count(), rig.vertex_count());
  } else {
    std::snprintf(line, sizeof line, "wrote %s (%zu vertices, %zu shapes, %ju bytes)", output.c_str(),
                  rig.vertex_count(), rig.shape_count(), bytes);
  }
  std::string summary = line;
  if (dropped > 0) summary += "; neutral only: the rig's " + std::to_string(dropped) + " shapes not written";
  const bool obj = folder || std::filesystem::path(output).extension() == ".obj";
  if (obj && rig.units() != Units::kUnknown) {
    summary += std::string("; units ") + ToString(rig.units()) + ", which OBJ does not store (read it back with --units " +
               ToString(rig.units()) + ")";
  }
  return summary + "\n";
}

// An OBJ file holds no blend shapes: refused (exit 2) for a rig that has some, rather than dropping them.
int RefuseShapesInObj(const std::string& output, std::size_t shape_count) {
  const std::filesystem::path folder = std::filesystem::path(output).replace_extension();
  std::fprintf(stderr,
               "facerig convert: %s: an OBJ file holds no blend shapes and the rig has %zu; write a folder instead "
               "(%s/: neutral.obj and one OBJ per shape, read back as a template folder), or add --neutral-only "
               "for the neutral alone\n",
               output.c_str(), shape_count, folder.c_str());
  return kUsageExitCode;
}

int RunConvert(const RigFileOptions& options) {
  try {
    const auto start = std::chrono::steady_clock::now();
    const std::string& output = options.paths[1];
    const bool folder = IsFolderOutput(output);
    CheckWritable({output, options.report});
    StandardShapesReport names;
    StageProgress("load", 0, 2);
    Rig rig = NameShapesForWriting(Load(options.paths[0], options.folder), options.naming, &names);
    const std::size_t dropped = options.neutral_only ? rig.shape_count() : 0;
    if (options.neutral_only) rig = NeutralOnly(rig);
    const bool obj = !folder && std::filesystem::path(output).extension() == ".obj";
    if (obj && rig.shape_count() > 0) return RefuseShapesInObj(output, rig.shape_count());
    const double load_seconds = SecondsSince(start);
    CommandReport report{"convert", {{"rig", options.paths[0]}}, {{"rig", output}}, SpeechAndBlinkWarnings(rig)};
    for (const RigWarning& warning : report.warnings) {  // the naming warnings were printed as the names were made
      std::fprintf(stderr, "facerig: warning: %s\n", warning.message.c_str());
    }
    AddShapeNamingWarnings(names, report.warnings);
    std::uintmax_t bytes = 0;
    // One set: an OBJ's MTL and images (and the report) arrive with it, or nothing changes.
    WriteOutputSet([&](OutputSet& set) {
      if (folder) {
        WriteRigObjFolder(AddObjFolderOutput(set, output, "OUT"), rig);
      } else {
        const std::filesystem::path written = WriteWithFilesBeside(
            set, output, [&](const std::filesystem::path& path) { SaveRig(path, rig); });
        CheckAfterWrite("rig", written);
        bytes = std::filesystem::file_size(written);
      }
      report.timings = {{"load", load_seconds}, {"total", SecondsSince(start)}};
      report.result = {{"vertices", rig.vertex_count()},
                       {"triangles", rig.triangle_count()},
                       {"shapes", rig.shape_count()},
                       {"shapes_not_written", dropped},
                       {"shape_names", ShapeNamesJson(options.naming, names)},
                       {"bytes", bytes}};
      WriteReport(set, options.report, report);
      StageProgress("write", 1, 2);  // before the set is committed: a stop here writes nothing
    });
    std::fputs(ConvertSummary(output, rig, folder, dropped, bytes).c_str(), stdout);
    return 0;
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

// The head's files (and previews) under their temporary names in `set`;
// returns what to print once they are in place.
std::string WriteDefaultHeadFiles(const Rig& rig, const DefaultHeadOptions& options, OutputSet& set) {
  namespace fs = std::filesystem;
  std::string written;
  char line[1024];
  for (const char* name : {"default_head.glb", "default_head.frig"}) {
    const fs::path path = fs::path(options.out_dir) / name;
    const fs::path temporary = set.Add(path, OutputSet::Kind::kFile);
    SaveRig(temporary, rig);
    CheckAfterWrite(fs::path(name).extension().string().substr(1), temporary);
    std::snprintf(line, sizeof line, "wrote %s (%zu vertices, %zu triangles, %zu shapes, %ju bytes)\n", path.c_str(),
                  rig.vertex_count(), rig.triangle_count(), rig.shape_count(),
                  static_cast<std::uintmax_t>(fs::file_size(temporary)));
    written += line;
  }
  const fs::path info = fs::path(options.out_dir) / "default_head.template.json";
  const fs::path info_temporary = set.Add(info, OutputSet::Kind::kFile);
  WriteFileAtomically(info_temporary, FaceTemplateInfoToJson(DefaultHeadTemplateInfo(rig)));
  CheckAfterWrite("template-info", info_temporary);
  written += "wrote " + info.string() + "\n";
  if (!options.preview_dir.empty()) {
    const ReplaceableFolder previews{[](const fs::path& name) { return name.extension() == ".png"; }, "PNG files",
                                     "--preview"};
    const fs::path preview_temporary = set.Add(options.preview_dir, OutputSet::Kind::kFolder, previews);
    for (const fs::path& path : WriteDefaultHeadPreviews(rig, preview_temporary, options.preview_size)) {
      written += "wrote " + (fs::path(options.preview_dir) / path.filename()).string() + "\n";
    }
    CheckAfterWrite("previews", preview_temporary);
  }
  return written;
}

CommandReport DefaultHeadReport(const DefaultHeadOptions& options, const Rig& rig,
                                const DefaultHeadFeatures& features) {
  const std::filesystem::path dir = options.out_dir;
  CommandReport report{"default-head",
                       {},
                       {{"rig", (dir / "default_head.glb").string()},
                        {"frig", (dir / "default_head.frig").string()},
                        {"template_info", (dir / "default_head.template.json").string()},
                        {"previews", options.preview_dir}},
                       SpeechAndBlinkWarnings(rig)};
  report.result = {{"control_vertices", features.control_vertex_count},
                   {"control_triangles", features.control_triangle_count},
                   {"vertices", rig.vertex_count()},
                   {"triangles", rig.triangle_count()},
                   {"shapes", rig.shape_count()}};
  return report;
}

// Writes default_head.{glb,frig} and its descriptor (the build runs it into
// build/data), previews and the report, as one set (output_set.h).
int MakeDefaultHead(const DefaultHeadOptions& options) {
  // OUT_DIR is made (in a folder that exists) before the head is built, and every output checked.
  CheckWritable(options.out_dir);
  const bool made = std::filesystem::create_directory(options.out_dir);
  try {
    CheckWritable({(std::filesystem::path(options.out_dir) / "default_head.glb").string(), options.preview_dir,
                   options.report});
  } catch (const std::exception&) {
    if (made) std::filesystem::remove(options.out_dir);  // nothing of this run stays
    throw;
  }
  const auto start = std::chrono::steady_clock::now();
  DefaultHeadFeatures features;
  StageProgress("build", 0, 2);
  const Rig head = BuildDefaultHead(&features);
  const double build_seconds = SecondsSince(start);
  std::printf("default head: control face %u vertices, %u triangles -> skin %u vertices\n",
              features.control_vertex_count, features.control_triangle_count,
              features.skin_vertex_count);
  StandardShapesReport names;
  const Rig rig = NameShapesForWriting(head, options.naming, &names);
  std::string written;
  WriteOutputSet([&](OutputSet& set) {
    written = WriteDefaultHeadFiles(rig, options, set);
    CommandReport report = DefaultHeadReport(options, rig, features);
    AddShapeNamingWarnings(names, report.warnings);
    report.result["shape_names"] = ShapeNamesJson(options.naming, names);
    report.timings = {{"build", build_seconds}, {"total", SecondsSince(start)}};
    WriteReport(set, options.report, report);
    StageProgress("write", 1, 2);  // before the set is committed: a stop here writes nothing
  });
  std::fputs(written.c_str(), stdout);
  return 0;
}

int RunDefaultHead(const DefaultHeadOptions& options) {
  return RunWritingCommand([&options] { return MakeDefaultHead(options); });
}

}  // namespace

void AddInspectCommand(CLI::App& facerig, CommandBody& body) {
  const auto [inspect, options] =
      AddSubcommand(facerig, body, "inspect", "print a rig's vertices, parts, shapes and sparsity", "", RunInspect);
  inspect->add_option("rig", options->paths, "FILE|DIR: the rig")->required()->expected(1);
  inspect->add_option("--json", options->report, "also write a JSON report (counts, shape names, warnings)");
  AddFolderOptions(*inspect, options->folder);
}

void AddConvertCommand(CLI::App& facerig, CommandBody& body) {
  const auto [convert, options] =
      AddSubcommand(facerig, body, "convert", "convert a rig between formats", "", RunConvert);
  convert->add_option("files", options->paths,
                      "IN OUT; OUT ending in '/' (or a folder): neutral.obj and one OBJ per shape, as --obj-dir")
      ->required()
      ->expected(2);
  convert->add_option("--json", options->report, "also write a JSON report");
  convert->add_flag("--neutral-only", options->neutral_only,
                    "write the neutral without the shapes (needed for an .obj OUT of a rig with shapes: an OBJ file "
                    "holds none)");
  AddShapeNamingOptions(*convert, options->naming);
  AddFolderOptions(*convert, options->folder);
}

void AddDefaultHeadCommand(CLI::App& facerig, CommandBody& body) {
  const auto [head, options] =
      AddSubcommand(facerig, body, "default-head", "write the built-in head (.glb and .frig)", "", RunDefaultHead);
  head->add_option("out_dir", options->out_dir,
                   "OUT_DIR: where to write default_head.{glb,frig} (made if missing, in a folder that exists)")
      ->required();
  head->add_option("--preview", options->preview_dir, "also render previews into DIR");
  head->add_option("--preview-size", options->preview_size, "preview size in pixels (64-4096, default 256)")
      ->check(InRange(64, 4096));
  head->add_option("--json", options->report, "also write a JSON report");
  AddShapeNamingOptions(*head, options->naming);
}

}  // namespace facerig::cli
