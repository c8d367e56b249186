// facerig: inspect and convert rigs.
//   facerig inspect FILE|DIR [folder options]
//   facerig convert IN OUT   [folder options]
//   facerig default-head OUT_DIR [--preview DIR [--preview-size PX]]
// Formats by extension: a folder of OBJs, .obj (neutral only), .glb, .gltf, .frig.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "cli_build.h"
#include "cli_identity.h"
#include "cli_register.h"
#include "facerig/offline/default_head.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/offline/io/template_folder.h"

namespace {

constexpr const char* kUsage =
    "usage: facerig inspect FILE|DIR [options]\n"
    "       facerig convert IN OUT [options]\n"
    "       facerig landmarks MESH -o LM.json [--debug-png P] [--json REPORT]\n"
    "       facerig register --template DIR|RIG --target MESH -o FITTED.obj [--landmarks LM.json] [--json REPORT]\n"
    "       facerig build --template DIR|RIG --target MESH -o OUT.glb [--frig F] [--obj-dir DIR]\n"
    "                     [--mode classic|identity|displacement] [--landmarks LM.json] [--json REPORT]\n"
    "       facerig average -o AVG.obj FACE FACE... [--no-align] [--json REPORT]   (rigs or OBJs, one topology)\n"
    "       facerig caricature --rig RIG --average AVG --factor F -o OUT [--keep-deltas] [--json REPORT]\n"
    "       facerig morph --template RIG --target RIG -o OUT [--json REPORT]   (adds the identityMorph shape)\n"
    "       facerig default-head OUT_DIR [--preview DIR [--preview-size PX]]   (built-in head)\n"
    "Formats by extension: a template folder of OBJs, .obj (neutral only), .glb, .gltf, .frig.\n"
    "Options for template folders and .obj input:\n"
    "  --units mm|cm|m        units of the input (default: guessed from the head size)\n"
    "  --up y|z               up axis of the input (default y)\n"
    "  --neutral FILE         neutral OBJ inside the folder\n"
    "  --shapes a,b,c         expression names (default: vertex_indices.json, else --glob)\n"
    "  --glob PATTERN         expression files (default *.obj)\n"
    "  --drop-threshold REL   drop deltas shorter than REL x bounding diagonal (default 1e-6)\n";

struct Arguments {
  std::vector<std::string> positional;
  facerig::TemplateImportOptions folder;
};

std::vector<std::string> SplitComma(const std::string& text) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::size_t end = comma == std::string::npos ? text.size() : comma;
    if (end > start) items.push_back(text.substr(start, end - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

// Returns false (after printing why) on a bad command line.
bool ParseArguments(int argc, char** argv, Arguments& args) {
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (arg.rfind("--", 0) != 0) {
      args.positional.push_back(arg);
      continue;
    }
    const char* v = value();
    if (!v) {
      std::fprintf(stderr, "facerig: %s needs a value\n", arg.c_str());
      return false;
    }
    if (arg == "--units") {
      const auto units = facerig::ParseUnits(v);
      if (!units) {
        std::fprintf(stderr, "facerig: --units '%s' is not mm, cm or m\n", v);
        return false;
      }
      args.folder.units = *units;
    } else if (arg == "--up") {
      const std::string up = v;
      if (up != "y" && up != "z" && up != "Y" && up != "Z") {
        std::fprintf(stderr, "facerig: --up '%s' is not y or z\n", v);
        return false;
      }
      args.folder.up_axis = (up == "z" || up == "Z") ? facerig::UpAxis::kZ : facerig::UpAxis::kY;
    } else if (arg == "--neutral") {
      args.folder.neutral_file = v;
    } else if (arg == "--shapes") {
      args.folder.shape_names = SplitComma(v);
    } else if (arg == "--glob") {
      args.folder.glob = v;
    } else if (arg == "--drop-threshold") {
      char* end = nullptr;
      const double rel = std::strtod(v, &end);
      if (end == v || *end != '\0' || !(rel >= 0.0) || rel > 1.0) {
        std::fprintf(stderr, "facerig: --drop-threshold '%s' is not a number in [0, 1]\n", v);
        return false;
      }
      args.folder.relative_drop_threshold = static_cast<float>(rel);
    } else {
      std::fprintf(stderr, "facerig: unknown option %s\n%s", arg.c_str(), kUsage);
      return false;
    }
  }
  return true;
}

facerig::Rig Load(const std::string& path, const Arguments& args) {
  if (std::filesystem::is_directory(path)) {
    facerig::TemplateImportReport report;
    facerig::Rig rig = facerig::ImportTemplateFolder(path, args.folder, &report);
    std::printf("imported %s: neutral %s, units %s%s, drop threshold %.3g (%zu small deltas dropped, "
                "longest %.3g), %zu vertices with several UVs (first kept)\n",
                path.c_str(), report.neutral_path.c_str(), facerig::ToString(report.units),
                report.units_guessed ? " (guessed from size)" : "", report.drop_threshold,
                report.dropped_entries, report.largest_dropped, report.uv_seam_vertices);
    return rig;
  }
  return facerig::LoadRigOrTemplateFolder(path, args.folder);
}

void Inspect(const facerig::Rig& rig) {
  std::printf("vertices %zu, triangles %zu, UVs %s, units %s, up %s, normal deltas %s\n",
              rig.vertex_count(), rig.triangle_count(), rig.uvs().empty() ? "no" : "yes",
              facerig::ToString(rig.units()), facerig::ToString(rig.up_axis()),
              rig.has_normal_deltas() ? "yes" : "no");
  std::printf("bounding diagonal %.4g %s\n", static_cast<double>(rig.bounding_diagonal()),
              facerig::ToString(rig.units()));
  std::printf("\nparts (%zu):\n  %-24s %18s %18s\n", rig.parts().size(), "name", "triangles",
              "vertex span");
  for (const facerig::Part& part : rig.parts()) {
    std::printf("  %-24s %8u +%-9u %8u +%-9u\n", part.name.c_str(), part.first_triangle,
                part.triangle_count, part.first_vertex, part.vertex_count);
  }
  std::printf("\nshapes (%zu):\n  %-24s %9s %9s %12s\n", rig.shape_count(), "name", "vertices",
              "% of mesh", "max delta");
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const facerig::BlendShapeView shape = rig.shape(s);
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

// --- default-head: writes default_head.{glb,frig} (the build runs it into build/data) and previews ---
int DefaultHeadCommand(int argc, char** argv) {
  std::string out_dir, preview_dir;
  int preview_size = 256;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--preview" && i + 1 < argc) {
      preview_dir = argv[++i];
    } else if (arg == "--preview-size" && i + 1 < argc) {
      preview_size = std::clamp(std::atoi(argv[++i]), 64, 4096);
    } else if (arg.rfind("--", 0) != 0 && out_dir.empty()) {
      out_dir = arg;
    } else {
      std::fputs(kUsage, stderr);
      return 2;
    }
  }
  if (out_dir.empty()) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  facerig::DefaultHeadFeatures features;
  const facerig::Rig rig = facerig::BuildDefaultHead(&features);
  std::printf("default head: control face %u vertices, %u triangles -> skin %u vertices\n",
              features.control_vertex_count, features.control_triangle_count,
              features.skin_vertex_count);
  std::filesystem::create_directories(out_dir);
  for (const char* name : {"default_head.glb", "default_head.frig"}) {
    const std::filesystem::path path = std::filesystem::path(out_dir) / name;
    facerig::SaveRig(path, rig);
    std::printf("wrote %s (%zu vertices, %zu triangles, %zu shapes, %ju bytes)\n", path.c_str(),
                rig.vertex_count(), rig.triangle_count(), rig.shape_count(),
                static_cast<std::uintmax_t>(std::filesystem::file_size(path)));
  }
  std::printf("wrote %s\n", facerig::WriteDefaultHeadTemplateInfo(rig, out_dir).c_str());
  if (!preview_dir.empty()) {
    for (const auto& path : facerig::WriteDefaultHeadPreviews(rig, preview_dir, preview_size)) {
      std::printf("wrote %s\n", path.c_str());
    }
  }
  return 0;
}
// --- end of default-head --------------------------------------------------------

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const std::string command = argv[1];
  if (command == "landmarks") return facerig::cli::RunLandmarksCommand(argc, argv);
  if (command == "register") return facerig::cli::RunRegisterCommand(argc, argv);
  if (command == "average") return facerig::cli::RunAverageCommand(argc, argv);
  if (command == "caricature") return facerig::cli::RunCaricatureCommand(argc, argv);
  if (command == "morph") return facerig::cli::RunMorphCommand(argc, argv);
  if (command == "build") return facerig::cli::RunBuildCommand(argc, argv);
  if (command == "default-head") {
    try {
      return DefaultHeadCommand(argc, argv);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "facerig: %s\n", error.what());
      return 1;
    }
  }
  Arguments args;
  if (!ParseArguments(argc, argv, args)) return 2;
  try {
    if (command == "inspect" && args.positional.size() == 1) {
      const auto start = std::chrono::steady_clock::now();
      const facerig::Rig rig = Load(args.positional[0], args);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("%s (loaded in %.3f s)\n", args.positional[0].c_str(), seconds);
      Inspect(rig);
      return 0;
    }
    if (command == "convert" && args.positional.size() == 2) {
      const facerig::Rig rig = Load(args.positional[0], args);
      facerig::SaveRig(args.positional[1], rig);
      std::printf("wrote %s (%zu vertices, %zu shapes, %ju bytes)\n", args.positional[1].c_str(),
                  rig.vertex_count(), rig.shape_count(),
                  static_cast<std::uintmax_t>(std::filesystem::file_size(args.positional[1])));
      return 0;
    }
  } catch (const facerig::IoError& error) {
    std::fprintf(stderr, "facerig: %s\n", error.what());
    return 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "facerig: %s\n", error.what());
    return 1;
  }
  std::fputs(kUsage, stderr);
  return 2;
}
