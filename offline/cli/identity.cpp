#include "cli/commands.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cli/common.h"
#include "cli/names.h"
#include "cli/options.h"
#include "facerig/runtime/ascii_case.h"
#include "facerig/offline/identity/caricature.h"
#include "facerig/offline/transfer/displacement_transfer.h"
#include "facerig/runtime/error.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/rig_builder.h"
#include "facerig/runtime/rig_warnings.h"

namespace facerig::cli {
namespace {

struct AverageOptions {
  std::string output, report_path;
  std::vector<std::string> face_paths;
  bool align = true;
};

struct CaricatureOptions {
  std::string rig_path, average_path, output, report_path;
  float factor = 0.0f;
  bool keep_deltas = false;
  bool align = true;
  StandardShapesOptions naming;
};

struct MorphOptions {
  std::string template_path, target_path, output, report_path;
  StandardShapesOptions naming;
};

// False (after printing why) when the output cannot hold what the command makes.
bool CheckOutputExtension(const std::string& path, bool allow_obj) {
  const std::string extension = LowerExtension(path);
  if (extension == ".glb" || extension == ".gltf" || extension == ".frig" || (allow_obj && extension == ".obj")) {
    return true;
  }
  std::fprintf(stderr, "facerig: -o '%s' must end in %s\n", path.c_str(),
               allow_obj ? ".obj, .glb, .gltf or .frig" : ".glb, .gltf or .frig (an OBJ holds no shapes)");
  return false;
}

// Throws std::runtime_error naming both files when `b` is not of `a`'s topology and units.
void CheckSameTopology(const Rig& a, const std::string& a_path, const Rig& b, const std::string& b_path) {
  if (b.vertex_count() != a.vertex_count()) {
    throw std::runtime_error(b_path + " has " + std::to_string(b.vertex_count()) + " vertices, " + a_path +
                             " has " + std::to_string(a.vertex_count()) + ": not the same topology");
  }
  if (b.triangle_count() != a.triangle_count() ||
      !std::equal(a.triangles().begin(), a.triangles().end(), b.triangles().begin())) {
    throw std::runtime_error(b_path + " has different triangles from " + a_path + ": not the same topology");
  }
  if (a.units() != Units::kUnknown && b.units() != Units::kUnknown && a.units() != b.units()) {
    throw std::runtime_error(b_path + " is in " + ToString(b.units()) + ", " + a_path + " in " +
                             ToString(a.units()));
  }
}

// Two rigs that must share one topology and units (CheckSameTopology).
std::pair<Rig, Rig> LoadRigsOfOneTopology(const std::string& a_path, const std::string& b_path) {
  Rig a = LoadRigOrTemplateFolder(a_path);
  Rig b = LoadRigOrTemplateFolder(b_path);
  CheckSameTopology(a, a_path, b, b_path);
  return {std::move(a), std::move(b)};
}

Rig BuildOrThrow(RawRig raw, const std::string& what) {
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  if (!rig) throw std::runtime_error(what + ": invalid rig: " + problem);
  return std::move(*rig);
}

// The rig (or OBJ with its MTL and images, by `output`'s extension) and the
// report, as one set.
void WriteRigSet(const std::string& output, const Rig& rig, const std::string& report_path,
                 const CommandReport& report) {
  WriteOutputSet([&](OutputSet& set) {
    const std::filesystem::path temporary =
        WriteWithFilesBeside(set, output, [&rig](const std::filesystem::path& path) { SaveRig(path, rig); });
    CheckAfterWrite("rig", temporary);
    WriteReport(set, report_path, report);
  });
}

// " cm", or nothing for a mesh of unknown units (an OBJ).
std::string UnitsSuffix(const Rig& rig) {
  return rig.units() == Units::kUnknown ? std::string() : std::string(" ") + ToString(rig.units());
}

float MaxDistance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  float worst = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - b[v]));
  return worst;
}

int RunAverage(const AverageOptions& options) {
  const auto& [output, report_path, face_paths, align] = options;
  if (!CheckOutputExtension(output, true)) return kUsageExitCode;
  try {
    const auto start = std::chrono::steady_clock::now();
    CheckWritable({output, report_path});
    std::optional<Rig> first;
    std::vector<std::vector<glm::vec3>> faces;
    for (const std::string& path : face_paths) {
      Rig face = LoadRigOrTemplateFolder(path);
      if (first) {
        CheckSameTopology(*first, face_paths[0], face, path);
      } else if (face.vertex_count() < 3) {
        throw std::runtime_error(path + " has " + std::to_string(face.vertex_count()) + " vertices: not a face");
      }
      faces.emplace_back(face.positions().begin(), face.positions().end());
      if (!first) first.emplace(std::move(face));
    }
    const std::vector<glm::vec3> average = AverageFace(faces, align);
    RawRig raw = RigBuilder::ToRaw(*first);
    raw.positions = average;
    raw.normals.clear();
    raw.shapes.clear();
    const Rig rig = BuildOrThrow(std::move(raw), "average");
    float spread = 0.0f;
    for (const auto& face : faces) spread = std::max(spread, MaxDistance(face, average));
    CommandReport report{"average", {}, {{"rig", output}}};
    for (const std::string& path : face_paths) report.inputs.push_back({"face", path});
    report.timings = {{"total", SecondsSince(start)}};
    report.result = {{"faces", face_paths.size()},
                     {"vertices", rig.vertex_count()},
                     {"aligned", align},
                     {"largest_distance_from_average", spread},
                     {"units", ToString(rig.units())}};
    WriteRigSet(output, rig, report_path, report);
    std::printf("wrote %s: average of %zu faces (%zu vertices%s); largest vertex distance from it %g%s\n",
                output.c_str(), faces.size(), rig.vertex_count(), align ? ", rigidly aligned" : "",
                static_cast<double>(spread), UnitsSuffix(rig).c_str());
    return 0;
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

int RunCaricature(const CaricatureOptions& options) {
  const auto& [rig_path, average_path, output, report_path, factor, keep_deltas, align, naming] = options;
  if (!CheckOutputExtension(output, false)) return kUsageExitCode;
  try {
    const auto start = std::chrono::steady_clock::now();
    CheckWritable({output, report_path});
    const auto [rig, average_rig] = LoadRigsOfOneTopology(rig_path, average_path);
    std::vector<glm::vec3> average(average_rig.positions().begin(), average_rig.positions().end());
    double alignment_rms = 0.0;
    if (align) {
      const SimilarityTransform motion = FitRigid(average, rig.positions(), {}, &alignment_rms);
      for (glm::vec3& p : average) p = motion.Apply(p);
    }
    const double load_seconds = SecondsSince(start);
    CaricatureParams params;
    params.factor = factor;
    params.expressions =
        keep_deltas ? CaricatureExpressions::kKeepDeltas : CaricatureExpressions::kDeformationTransfer;
    const auto caricature_start = std::chrono::steady_clock::now();
    // Baked visemes are made again from the caricature's shapes, not transferred.
    std::optional<Rig> without_visemes;
    if (naming.visemes == VisemeTargets::kOculus) without_visemes = WithoutBakedVisemes(rig);
    const Rig& source = without_visemes ? *without_visemes : rig;
    StandardShapesReport names;
    const Rig result =
        NameShapesForWriting(BuildOrThrow(CaricatureRig(source, average, params), "caricature"), naming, &names);
    const double caricature_seconds = SecondsSince(caricature_start);
    const float moved = MaxDistance(result.positions(), rig.positions());
    CommandReport report{"caricature",
                         {{"rig", rig_path}, {"average", average_path}},
                         {{"rig", output}},
                         SpeechAndBlinkWarnings(result)};
    AddShapeNamingWarnings(names, report.warnings);
    report.timings = {{"load", load_seconds}, {"caricature", caricature_seconds}, {"total", SecondsSince(start)}};
    report.result = {{"factor", factor},
                     {"expressions", keep_deltas ? "keep-deltas" : "deformation-transfer"},
                     {"aligned", align},
                     {"alignment_rms", alignment_rms},
                     {"largest_neutral_displacement", moved},
                     {"vertices", result.vertex_count()},
                     {"shapes", result.shape_count()},
                     {"shape_names", ShapeNamesJson(naming, names)}};
    WriteRigSet(output, result, report_path, report);
    std::printf(
        "wrote %s: caricature factor %g of %s (%zu vertices, %zu shapes, expressions %s); neutral moved "
        "up to %g%s; %.2f s\n",
        output.c_str(), static_cast<double>(factor), rig_path.c_str(), result.vertex_count(),
        result.shape_count(), keep_deltas ? "deltas kept" : "by deformation transfer", static_cast<double>(moved),
        UnitsSuffix(result).c_str(), SecondsSince(start));
    return 0;
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

int RunMorph(const MorphOptions& options) {
  const auto& [template_path, target_path, output, report_path, naming] = options;
  if (!CheckOutputExtension(output, false)) return kUsageExitCode;
  try {
    const auto start = std::chrono::steady_clock::now();
    CheckWritable({output, report_path});
    const auto [template_rig, target_rig] = LoadRigsOfOneTopology(template_path, target_path);
    if (target_rig.FindShape(kIdentityMorphShape)) {
      throw std::runtime_error(target_path + " already has a shape called " + kIdentityMorphShape);
    }
    StandardShapesReport names;
    const Rig result =
        NameShapesForWriting(BuildOrThrow(IdentityMorphRig(template_rig, target_rig), "identity morph"), naming, &names);
    const float morph = MaxDistance(template_rig.positions(), target_rig.positions());
    CommandReport report{"morph",
                         {{"template", template_path}, {"target", target_path}},
                         {{"rig", output}},
                         SpeechAndBlinkWarnings(result)};
    AddShapeNamingWarnings(names, report.warnings);
    report.timings = {{"total", SecondsSince(start)}};
    report.result = {{"vertices", result.vertex_count()},
                     {"shapes", result.shape_count()},
                     {"identity_shape", kIdentityMorphShape},
                     {"shape_names", ShapeNamesJson(naming, names)},
                     {"largest_identity_displacement", morph}};
    WriteRigSet(output, result, report_path, report);
    std::printf("wrote %s: %zu vertices, %zu shapes (the target's %zu + %s, moving vertices up to %g%s); %.2f s\n",
                output.c_str(), result.vertex_count(), result.shape_count(), target_rig.shape_count(),
                kIdentityMorphShape, static_cast<double>(morph), UnitsSuffix(result).c_str(), SecondsSince(start));
    return 0;
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

}  // namespace

void AddAverageCommand(CLI::App& facerig, CommandBody& body) {
  const auto [average, options] = AddSubcommand(facerig, body, "average", "the mean face of corresponded faces",
      "Faces: rigs or OBJs of one topology and units. Each face is first rigidly aligned onto the first\n"
      "(unless --no-align). The output has the first face's topology, UVs and parts and no shapes.",
      RunAverage);
  average->add_option("faces", options->face_paths, "two or more faces")->required()->expected(2, CLI::detail::expected_max_vector_size);
  AddOffFlag(*average, "--no-align", options->align, "do not align the faces rigidly first");
  AddOutputOptions(*average, options->output, options->report_path, "output (.obj, .glb, .gltf or .frig)");
}

void AddCaricatureCommand(CLI::App& facerig, CommandBody& body) {
  const auto [caricature, options] = AddSubcommand(facerig, body, "caricature", "scale a rig's difference from the average face",
      "neutral + F x (neutral - average), F in [-1, 3] (-1 the average, 0 the rig itself). The\n"
      "expressions follow by deformation transfer from the rig's own shapes, or keep their deltas\n"
      "(--keep-deltas). The average is rigidly aligned onto the rig first (unless --no-align); it needs\n"
      "the rig's vertex count.",
      RunCaricature);
  caricature->add_option("--rig", options->rig_path, "the rig")->required();
  caricature->add_option("--average", options->average_path, "the average face (.obj or a rig)")->required();
  caricature->add_option("--factor", options->factor, "F in [-1, 3]")
      ->required()
      ->check(InRange(kMinCaricatureFactor, kMaxCaricatureFactor));
  caricature->add_flag("--keep-deltas", options->keep_deltas, "keep the expressions' deltas");
  AddOffFlag(*caricature, "--no-align", options->align, "do not align the average rigidly first");
  AddOutputOptions(*caricature, options->output, options->report_path, "output rig (.glb, .gltf or .frig)");
  AddShapeNamingOptions(*caricature, options->naming);
}

void AddMorphCommand(CLI::App& facerig, CommandBody& body) {
  const auto [morph, options] = AddSubcommand(facerig, body, "morph", "add the identityMorph shape between two rigs",
      "The template's neutral, the target's shapes (e.g. from a transfer onto the target) and one more\n"
      "shape, identityMorph: at 0 the template's face, at 1 the target's, the expressions working at any\n"
      "weight. Both rigs need the same topology.",
      RunMorph);
  morph->add_option("--template", options->template_path, "the template rig")->required();
  morph->add_option("--target", options->target_path, "the target rig, on the template's topology")->required();
  AddOutputOptions(*morph, options->output, options->report_path, "output rig (.glb, .gltf or .frig)");
  AddShapeNamingOptions(*morph, options->naming);
}

}  // namespace facerig::cli
