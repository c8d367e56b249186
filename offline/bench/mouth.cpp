#include "bench/mouth.h"

#include <array>
#include <cstdio>
#include <stdexcept>
#include <tuple>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/common.h"
#include "bench/json.h"
#include "cli/options.h"
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/mapping/topology_mapping.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/rigging/lid_choice.h"
#include "facerig/offline/rigging/rig_build.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/offline/mapping/mouth_sides.h"
#include "measure/ict_vertex_ranges.h"
#include "measure/mouth_interior.h"

namespace {

struct MouthOptions {
  std::string ict_dir = FACERIG_DEFAULT_ICT_DIR;
  std::string json_path;
  std::string png_dir;
  int png_size = 320;
};

// One rig's opened mouth: its fold, and (for a built rig) its curtain.
struct MouthRow {
  std::string name;
  facerig::LipFold fold;
  std::optional<facerig::MouthCurtain> curtain;
};

// The head's mouth at jawOpen 1, close up from the front and from its side
// below (where the fold under the lower lip shows), part colours.
void RenderOpenMouth(const facerig::Rig& rig, const facerig::DefaultHeadFeatures& features,
                     const std::filesystem::path& directory, const std::string& name, int size) {
  std::vector<float> weights(rig.shape_count(), 0.0f);
  weights[rig.FindShape("jawOpen").value()] = 1.0f;
  std::vector<glm::vec3> positions(rig.vertex_count()), normals(rig.vertex_count());
  facerig::BlendJob job{&rig, weights, facerig::NormalMode::kRecompute, positions, normals};
  if (job.Run() != facerig::BlendJobError::kNone) throw std::runtime_error("mouth bench: blend failed");
  const glm::vec3 a = rig.positions()[features.mouth_corners[0]], b = rig.positions()[features.mouth_corners[1]];
  const float width = glm::length(a - b);
  const glm::vec3 centre = 0.5f * (a + b) - glm::vec3(0.0f, 0.35f * width, 0.0f);
  std::filesystem::create_directories(directory);
  for (const auto& [view_name, yaw, pitch] : {std::tuple<const char*, float, float>{"front", 0.0f, 0.0f},
                                              std::tuple<const char*, float, float>{"side", 1.2f, 0.1f}}) {
    const facerig::RasterView view = facerig::RasterView::Orbit(centre, 0.75f * width, size, size, yaw, pitch);
    const std::filesystem::path path = directory / (name + "_" + view_name + ".png");
    facerig::WritePng(path, facerig::RenderRig(rig, positions, normals, view));
    std::printf("wrote %s\n", path.string().c_str());
  }
}

void PrintRow(const MouthRow& row) {
  if (row.curtain) {
    const facerig::MouthCurtain& c = *row.curtain;
    std::printf("%-34s %8.1f %9.2f %9zu %9zu %9zu %9.2f %9.2f\n", row.name.c_str(), row.fold.degrees,
                row.fold.below_lip, c.upper_vertices, c.skin_on_jaw, c.sack_on_jaw, c.worst_ratio,
                c.lower_lip_motion);
  } else {
    std::printf("%-34s %8.1f %9.2f %9s %9s %9s %9s %9s\n", row.name.c_str(), row.fold.degrees, row.fold.below_lip,
                "-", "-", "-", "-", "-");
  }
}

nlohmann::json RowJson(const MouthRow& row) {
  nlohmann::json json = {{"name", row.name},
                         {"fold_degrees", row.fold.degrees},
                         {"fold_below_lip", row.fold.below_lip},
                         {"fold_edges", row.fold.edges}};
  if (row.curtain) {
    json["curtain"] = {{"upper_vertices", row.curtain->upper_vertices},
                       {"skin_on_jaw", row.curtain->skin_on_jaw},
                       {"sack_on_jaw", row.curtain->sack_on_jaw},
                       {"worst_ratio", row.curtain->worst_ratio},
                       {"lower_lip_motion", row.curtain->lower_lip_motion}};
  }
  return json;
}

// The same fitted rig mapped onto the head with other mouth sides: none
// (every vertex searches both lips), or each zone vertex's by its height
// alone (MouthSideParams::along_surface false, the previous rule).
facerig::Rig MappedWith(const facerig::Rig& ict, const facerig::FaceTemplateInfo& info,
                        const facerig::BuildRigResult& built, const facerig::RawRig& head,
                        std::optional<facerig::MouthSideParams> sides) {
  const facerig::Rig fitted_rig = facerig::RigBuilder::Build(built.fitted_rig).value();
  facerig::TopologyMappingParams params = facerig::BuildRigParams{}.mapping;
  params.openings = facerig::BuildRigParams{}.openings;
  const facerig::Mesh fitted{.positions = built.registration.positions,
                             .triangles = {ict.triangles().begin(), ict.triangles().end()}};
  const facerig::MouthSides mouth_sides =
      sides ? facerig::FindMouthSides(ict, built.registration.positions, built.registration.rigid.Inverse(),
                                      head.positions, head.triangles, info.region.last + 1, *sides)
            : facerig::MouthSides{};
  // The eye rims as the build snapped them are not rebuilt here: the mouth is what differs.
  const facerig::TopologyMapping mapping =
      facerig::ComputeTopologyMapping(fitted, facerig::NeutralMesh(head), params, {}, mouth_sides);
  return facerig::RigBuilder::Build(facerig::MapRigToTarget(fitted_rig, mapping, head)).value();
}

// The curtain with other shares of MouthSideParams::lower_share (0.8 by
// default): whether the result hinges on that value.
nlohmann::json SweepLowerShare(const facerig::Rig& ict, const facerig::FaceTemplateInfo& info,
                               const facerig::BuildRigResult& built, const facerig::RawRig& head,
                               const facerig::Rig& own, const facerig::DefaultHeadFeatures& features) {
  std::printf("\n  %-12s %9s %9s %9s\n", "lower_share", "skin on", "sack on", "worst");
  nlohmann::json sweep = nlohmann::json::array();
  for (float share : {0.6f, 0.7f, 0.8f, 0.9f, 1.0f}) {
    facerig::MouthSideParams params;
    params.lower_share = share;
    const facerig::MouthCurtain c = facerig::MeasureMouthCurtain(own, MappedWith(ict, info, built, head, params), features);
    std::printf("  %-12.2f %9zu %9zu %9.2f\n", share, c.skin_on_jaw, c.sack_on_jaw, c.worst_ratio);
    sweep.push_back({{"lower_share", share}, {"skin_on_jaw", c.skin_on_jaw}, {"sack_on_jaw", c.sack_on_jaw},
                     {"worst_ratio", c.worst_ratio}});
  }
  return sweep;
}

int Run(const MouthOptions& options) {
  nlohmann::json report;
  try {
    const facerig::Rig ict = facerig::ImportTemplateFolder(options.ict_dir);
    const facerig::FaceTemplateInfo info = facerig::ResolveFaceTemplateInfo(ict, options.ict_dir);
    facerig::DefaultHeadFeatures features;
    const facerig::Rig own = facerig::BuildDefaultHead(&features);
    facerig::RawRig head = facerig::RigBuilder::ToRaw(own);
    head.shapes.clear();  // only the template's shapes
    facerig::LandmarkDetector detector;
    const facerig::LandmarkResult detected = detector.Detect(facerig::NeutralMesh(head));
    const facerig::BuildRigResult built = facerig::BuildRigChoosingLids(
        facerig::TemplatePreparation(ict, info, {}), facerig::BuildTarget{.rig = head, .mesh = {}},
        info.landmark_vertices, detected.landmarks, detected.doubtful_lids, {});
    const facerig::Rig rig = facerig::RigBuilder::Build(built.rig).value();
    const facerig::Rig unsided = MappedWith(ict, info, built, head, std::nullopt);
    facerig::MouthSideParams by_height;
    by_height.along_surface = false;
    const facerig::Rig previous = MappedWith(ict, info, built, head, by_height);
    const facerig::Rig fitted = facerig::RigBuilder::Build(built.fitted_rig).value();
    // dlib's outer mouth corners (landmarks 48 and 54) on ICT's vertices; its skin: face, head and neck.
    const std::array<std::uint32_t, 2> ict_corners = {info.landmark_vertices.at(48), info.landmark_vertices.at(54)};
    const std::uint32_t ict_lip_bottom = info.landmark_vertices.at(57);
    const std::uint32_t ict_skin = facerig::test::ict::kSkin.end;

    const std::vector<MouthRow> rows = {
        {"this build", facerig::MeasureLipFold(rig, features), facerig::MeasureMouthCurtain(own, rig, features)},
        {"mouth sides by height (previous)", facerig::MeasureLipFold(previous, features),
         facerig::MeasureMouthCurtain(own, previous, features)},
        {"without mouth sides", facerig::MeasureLipFold(unsided, features),
         facerig::MeasureMouthCurtain(own, unsided, features)},
        {"the head's own jawOpen (reference)", facerig::MeasureLipFold(own, features), std::nullopt},
        {"ICT fitted, transferred (unmapped)", facerig::MeasureLipFold(fitted, ict_corners, ict_lip_bottom, ict_skin), std::nullopt},
        {"ICT-FaceKit's own jawOpen", facerig::MeasureLipFold(ict, ict_corners, ict_lip_bottom, ict_skin), std::nullopt},
    };
    std::printf("ICT-FaceKit (%s) onto the built-in head (%zu vertices), jawOpen at weight 1; mouth sides: %zu upper, "
                "%zu lower vertices\n\n",
                options.ict_dir.c_str(), own.vertex_count(), built.mapping.mouth_upper_vertices,
                built.mapping.mouth_lower_vertices);
    std::printf("%-34s %8s %9s %9s %9s %9s %9s %9s\n", "rig", "fold deg", "fold at", "upper", "skin on", "sack on",
                "worst", "lower lip");
    std::printf("%-34s %8s %9s %9s %9s %9s %9s %9s\n", "", "", "below lip", "mouth", "jaw", "jaw", "ratio", "moves cm");
    nlohmann::json json_rows = nlohmann::json::array();
    for (const MouthRow& row : rows) {
      PrintRow(row);
      json_rows.push_back(RowJson(row));
    }
    report["rows"] = json_rows;
    const MouthRow& current = rows.front();
    const std::size_t curtain = current.curtain->skin_on_jaw + current.curtain->sack_on_jaw;
    std::printf("\n  %-50s %8zu   target <= 0      %s\n", "upper-mouth vertices following the jaw", curtain,
                curtain == 0 ? "ok" : "MISSED");
    std::printf("  %-50s %8.1f   target <= 10     %s\n", "fold under the lower lip (degrees)", current.fold.degrees,
                current.fold.degrees <= 10.0f ? "ok" : "MISSED");
    report["summary"] = {{"curtain_vertices", curtain}, {"fold_degrees", current.fold.degrees}};
    report["lower_share_sweep"] = SweepLowerShare(ict, info, built, head, own, features);
    if (!options.png_dir.empty()) {
      RenderOpenMouth(rig, features, options.png_dir, "this_build", options.png_size);
      RenderOpenMouth(previous, features, options.png_dir, "previous", options.png_size);
      RenderOpenMouth(unsided, features, options.png_dir, "without_mouth_sides", options.png_size);
      RenderOpenMouth(own, features, options.png_dir, "own_jaw_open", options.png_size);
    }
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
  std::printf("\nupper mouth: head vertices above its lip seam, between its mouth corners, that its own jawOpen leaves\n"
              "(skin: the upper lip and its inner side; sack: the palate); on the jaw: the built jawOpen moves them\n"
              "over half its lower lip's median motion (worst ratio: the largest such motion over it). Fold: the\n"
              "largest change of the angle between neighbouring skin triangles under the lower lip (below its\n"
              "vermilion border, half a mouth width down, facing forward), neutral to jawOpen 1; fold at: how far\n"
              "below the border (cm).\n");
  return WriteBenchJson(options.json_path, report);
}

void AddOptions(CLI::App& app, MouthOptions& options) {
  app.add_option("--ict", options.ict_dir, "the ICT-FaceKit folder");
  app.add_option("--json", options.json_path, "write the results as JSON");
  app.add_option("--png", options.png_dir, "also render the opened mouth close up into DIR");
  app.add_option("--png-size", options.png_size, "render size in pixels (default 320)")
      ->check(facerig::cli::InRange(64, 4096));
}

}  // namespace

int RunMouthBenchmark(int argc, char** argv) {
  return ParseAndRunBench<MouthOptions>(argc, argv,
                                        "ICT-FaceKit's shapes on the built-in head: the opened mouth's curtain and fold",
                                        "facerig-bench mouth", AddOptions, Run);
}
