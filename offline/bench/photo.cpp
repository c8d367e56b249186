#include "bench/photo.h"

#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/common.h"
#include "bench/json.h"
#include "cli/app.h"
#include "facerig/runtime/error.h"
#include "facerig/offline/error.h"
#include "facerig/offline/io/image_codec.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/files/image_file.h"

namespace {

namespace fs = std::filesystem;

struct PhotoBenchOptions {
  std::string photo = FACERIG_DEFAULT_PHOTO;
  std::string template_dir = FACERIG_DEFAULT_ICT_DIR;
  int size = 1024;
  int runs = 3;
  std::string json;
};

void AddPhotoBenchOptions(CLI::App& app, PhotoBenchOptions& o) {
  app.add_option("--photo", o.photo, "the portrait (PNG or JPEG)")->capture_default_str();
  app.add_option("--template", o.template_dir, "a template folder with identity modes")->capture_default_str();
  app.add_option("--size", o.size, "the photo's longer side, pixels, before the command reads it")
      ->check(facerig::cli::InRange(128, 2048))
      ->capture_default_str();
  app.add_option("--runs", o.runs, "runs per pipeline (the median is reported)")
      ->check(facerig::cli::InRange(1, 20))
      ->capture_default_str();
  app.add_option("--json", o.json, "write the results as JSON");
}

// The portrait resized to `size` on its longer side, as a PNG in `folder`.
fs::path ResizedPhoto(const fs::path& photo, int size, const fs::path& folder) {
  cv::Mat image;
  try {
    image = facerig::DecodeImageBytes(facerig::ReadImageFile(photo).bytes, facerig::DecodedChannels::kBgr);
  } catch (const facerig::InvalidInputError& error) {
    throw facerig::IoError(facerig::IoErrorKind::kParse, photo.string(), error.what());
  }
  const double scale = static_cast<double>(size) / std::max(image.cols, image.rows);
  cv::Mat resized;
  cv::resize(image, resized, cv::Size(), scale, scale, scale > 1.0 ? cv::INTER_CUBIC : cv::INTER_AREA);
  const fs::path path = folder / ("photo_" + std::to_string(size) + ".png");
  const std::vector<std::uint8_t> png = facerig::EncodePngBytes(resized);
  facerig::WriteFileAtomically(path, std::as_bytes(std::span(png)));
  return path;
}

// One `facerig photo` run in this process; its report's step timings.
nlohmann::json RunPhotoCommand(const fs::path& photo, const std::string& template_dir, const fs::path& out,
                               bool shading) {
  fs::remove_all(out);
  fs::create_directories(out);
  std::vector<std::string> arguments = {"facerig", "photo", photo.string(), "-o", (out / "head.glb").string(),
                                        "--template", template_dir, "--frig", (out / "head.frig").string(),
                                        "--obj-dir", (out / "obj").string(), "--json", (out / "report.json").string()};
  if (!shading) arguments.push_back("--no-shading-fit");
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  if (facerig::cli::RunFacerig(static_cast<int>(argv.size()), argv.data()) != 0) {
    throw std::runtime_error("facerig photo failed on " + photo.string());
  }
  std::ifstream in(out / "report.json");
  return nlohmann::json::parse(in)["timings"];
}

constexpr const char* kSteps[] = {"read", "detect", "template", "fit", "texture", "write", "total"};
constexpr double kTargetSeconds = 5.0;

// Each step's median over `runs` runs of one pipeline.
nlohmann::json MedianTimings(const fs::path& photo, const PhotoBenchOptions& o, const fs::path& out, bool shading) {
  nlohmann::json medians;
  std::vector<nlohmann::json> runs;
  for (int r = 0; r < o.runs; ++r) runs.push_back(RunPhotoCommand(photo, o.template_dir, out, shading));
  for (const char* step : kSteps) {
    std::vector<double> values;
    for (const nlohmann::json& timings : runs) values.push_back(timings.value(step, 0.0));
    medians[step] = UpperMedian(values);
  }
  return medians;
}

int RunPhoto(const PhotoBenchOptions& o) {
  try {
    const fs::path out = fs::temp_directory_path() / "facerig_bench_photo";
    fs::create_directories(out);
    const fs::path photo = ResizedPhoto(o.photo, o.size, out);
    // The template cache (template_cache.h) this run's own, filled by a first
    // run; then the same without it, as before the cache.
    setenv("FACERIG_CACHE_DIR", (out / "template_cache").c_str(), 1);
    RunPhotoCommand(photo, o.template_dir, out / "run", true);
    const nlohmann::json refined = MedianTimings(photo, o, out / "run", true);
    const nlohmann::json landmarks_only = MedianTimings(photo, o, out / "run", false);
    setenv("FACERIG_CACHE_DIR", "off", 1);
    const nlohmann::json uncached = MedianTimings(photo, o, out / "run", true);
    unsetenv("FACERIG_CACHE_DIR");
    fs::remove_all(out);
    std::printf("\nfacerig photo, %d px, %s, --frig and --obj-dir; median of %d runs, seconds:\n", o.size,
                o.template_dir.c_str(), o.runs);
    std::printf("  %-10s %12s %22s %22s\n", "step", "default", "--no-shading-fit", "template cache off");
    for (const char* step : kSteps) {
      std::printf("  %-10s %12.3f %22.3f %22.3f\n", step, refined[step].get<double>(),
                  landmarks_only[step].get<double>(), uncached[step].get<double>());
    }
    const double total = refined["total"].get<double>();
    std::printf("  whole command %.2f s, target <= %.0f s: %s\n", total, kTargetSeconds,
                total <= kTargetSeconds ? "ok" : "MISSED");
    const nlohmann::json report = {{"benchmark", "photo"},        {"photo", o.photo},
                                   {"size", o.size},              {"template", o.template_dir},
                                   {"runs", o.runs},              {"target_seconds", kTargetSeconds},
                                   {"default", refined},          {"no_shading_fit", landmarks_only},
                                   {"template_cache_off", uncached}};
    return WriteBenchJson(o.json, report);
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
}

}  // namespace

int RunPhotoBenchmark(int argc, char** argv) {
  return ParseAndRunBench<PhotoBenchOptions>(argc, argv, "facerig photo timed per step, with and without the shading fit",
                                             "facerig-bench photo", AddPhotoBenchOptions, RunPhoto);
}
