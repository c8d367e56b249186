#include "cli/options.h"
#include "bench/proportions.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/common.h"
#include "bench/json.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/runtime/mesh.h"
#include "measure/face_proportions.h"

namespace {

using facerig::test::kProportions;
using facerig::test::Proportion;
using facerig::test::ProportionName;

struct ProportionsOptions {
  std::string head = FACERIG_DEFAULT_HEAD;
  std::string ict_dir = FACERIG_DEFAULT_ICT_DIR;
  int faces = 20;
  unsigned seed = 3401;  // the test uses other seeds
  double limit_sd = 2.0;
  bool dlib_pixels = false;
  std::string landmarks_png;
  std::string json_path;
};

void AddProportionsOptions(CLI::App& app, ProportionsOptions& options) {
  app.add_option("--head", options.head, "the head measured: a rig file or template folder (default: the built-in head)");
  app.add_option("--ict", options.ict_dir, "the ICT-FaceKit folder (the reference faces)");
  app.add_option("--faces", options.faces, "random ICT identities (default 20)")->check(facerig::cli::InRange(2, 100000));
  app.add_option("--seed", options.seed, "first random seed (default 3401)");
  app.add_option("--limit", options.limit_sd, "how many reference SDs count as in range (default 2)")
      ->check(facerig::cli::InRange(0.1, 100.0));
  app.add_flag("--dlib-pixels", options.dlib_pixels,
               "measure dlib's own points in the render (no calibration, no eyes on the lid margins)");
  app.add_option("--landmarks-png", options.landmarks_png, "write the head's render with its 68 points (PNG)");
  app.add_option("--json", options.json_path, "write the results as JSON");
}

nlohmann::json RatiosJson(const facerig::test::FaceProportions& p) {
  nlohmann::json json = {{"eye_distance", p.eye_distance}, {"eyes_fitted", p.eyes_fitted}};
  for (Proportion which : kProportions) json[ProportionName(which)] = p[which];
  return json;
}

int RunProportions(const ProportionsOptions& options) {
  try {
    const facerig::Rig head = facerig::LoadRigOrTemplateFolder(options.head);
    facerig::LandmarkDetector detector;
    const auto source = options.dlib_pixels ? facerig::test::LandmarkSource::kDlibPixels
                                            : facerig::test::LandmarkSource::kOnSurface;
    const facerig::Mesh head_mesh = facerig::NeutralMesh(head);
    const facerig::test::FaceProportions measured = facerig::test::MeasureFaceProportions(detector, head_mesh, source);
    if (!options.landmarks_png.empty()) {
      facerig::WritePng(options.landmarks_png, facerig::DrawLandmarks(detector.Detect(head_mesh)));
    }

    std::printf("reference: %d ICT-FaceKit random identities (seeds %u-%u), %s\n", options.faces, options.seed,
                options.seed + static_cast<unsigned>(options.faces) - 1, options.ict_dir.c_str());
    const facerig::test::IctFaceModel ict = facerig::test::LoadIctFaces(options.ict_dir);
    const facerig::test::ProportionReference reference =
        facerig::test::IctProportionReference(detector, ict, options.faces, options.seed, source);

    std::printf("head: %s (eye distance %.3f, %d eyes on their lid margins); points: %s\n\n", options.head.c_str(),
                measured.eye_distance, measured.eyes_fitted,
                options.dlib_pixels ? "dlib's own in the render" : "the detector's on the surface");
    std::printf("%-12s %9s %9s %9s %9s %9s %8s  %s\n", "ratio", "ICT mean", "ICT SD", "ICT min", "ICT max", "head",
                "z", "within");
    nlohmann::json rows = nlohmann::json::object();
    int outside = 0;
    for (Proportion which : kProportions) {
      const auto i = static_cast<std::size_t>(which);
      double lo = reference.faces.front().ratios[i], hi = lo;
      for (const auto& face : reference.faces) {
        lo = std::min(lo, face.ratios[i]);
        hi = std::max(hi, face.ratios[i]);
      }
      const double z = reference.ZScore(which, measured[which]);
      const bool within = std::abs(z) <= options.limit_sd;
      outside += within ? 0 : 1;
      std::printf("%-12s %9.4f %9.4f %9.4f %9.4f %9.4f %+8.2f  %s\n", ProportionName(which), reference.mean[i],
                  reference.sd[i], lo, hi, measured[which], z, within ? "ok" : "OUTSIDE");
      rows[ProportionName(which)] = {{"reference_mean", reference.mean[i]}, {"reference_sd", reference.sd[i]},
                                     {"reference_min", lo}, {"reference_max", hi},
                                     {"head", measured[which]}, {"z", z}, {"within", within}};
    }
    std::printf("\n%d of %zu ratios outside +-%g SD (eye opening: height / width; the others / eye distance)\n",
                outside, kProportions.size(), options.limit_sd);
    nlohmann::json faces = nlohmann::json::array();
    for (const auto& face : reference.faces) faces.push_back(RatiosJson(face));
    return WriteBenchJson(options.json_path,
                          {{"benchmark", "proportions"},
                           {"head", options.head},
                           {"head_ratios", RatiosJson(measured)},
                           {"reference", {{"ict_dir", options.ict_dir}, {"first_seed", options.seed},
                                          {"faces", faces}}},
                           {"limit_sd", options.limit_sd},
                           {"points", options.dlib_pixels ? "dlib_pixels" : "on_surface"},
                           {"ratios", rows},
                           {"outside", outside}});
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
}

}  // namespace

int RunProportionsBenchmark(int argc, char** argv) {
  return ParseAndRunBench<ProportionsOptions>(
      argc, argv, "the built-in head's face proportions against ICT-FaceKit's random identities (dlib's 68 points)",
      "facerig-bench proportions", AddProportionsOptions, RunProportions);
}
