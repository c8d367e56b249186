#include "cli/build_batch.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/error.h"

namespace facerig::cli {
namespace {

namespace fs = std::filesystem;

struct CastTarget {
  std::string path;  // as given, or inside a folder given
  std::string name;  // the file's stem: its outputs' names
};

// A file of a folder of targets: a mesh LoadBuildTarget reads (not a
// temporary or other hidden file).
bool IsTargetFile(const fs::directory_entry& entry) {
  const std::string name = entry.path().filename().string();
  const std::string extension = LowerExtension(entry.path());
  std::error_code error;
  return !name.starts_with(".") && entry.is_regular_file(error) &&
         (extension == ".obj" || extension == ".glb" || extension == ".gltf" || extension == ".frig");
}

// Every --target, folders replaced by their target files (sorted). A path
// that is no file is kept: it fails as that target, reported.
// \throw InvalidInputError when two targets would write the same outputs.
std::vector<CastTarget> ListTargets(const std::vector<std::string>& given) {
  std::vector<CastTarget> targets;
  for (const std::string& path : given) {
    std::error_code error;
    if (!fs::is_directory(path, error)) {
      targets.push_back({path, fs::path(path).stem().string()});
      continue;
    }
    std::vector<fs::path> files;
    for (const fs::directory_entry& entry : fs::directory_iterator(path, error)) {
      if (IsTargetFile(entry)) files.push_back(entry.path());
    }
    if (error) throw InvalidInputError("cannot list the targets in " + path + ": " + error.message());
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) targets.push_back({file.string(), file.stem().string()});
  }
  std::map<std::string, std::string> path_of_name;
  for (const CastTarget& target : targets) {
    const auto [at, added] = path_of_name.emplace(target.name, target.path);
    if (!added) {
      throw InvalidInputError("two targets are named '" + target.name + "' (" + at->second + " and " + target.path +
                              "): a cast writes NAME.glb and NAME.json per target");
    }
  }
  if (targets.empty()) throw InvalidInputError("no targets (.obj, .glb, .gltf, .frig) in the --target folders");
  return targets;
}

// What the summary says of one target.
struct CastEntry {
  CastTarget target;
  std::string rig, report, error;  // error empty: built
  double seconds = 0.0;
  TargetBuilt built;
};

// A failed target's report: its error, in place of the build's result.
void WriteFailureReport(const BuildOptions& options, const std::string& error, double seconds) {
  CommandReport report{"build", {{"template", options.template_path}, {"target", options.target_path}}};
  report.result = {{"status", "failed"}, {"error", error}};
  report.timings = {{"total", seconds}};
  WriteCommandReport(options.report, report);
}

// Builds one target of the cast; a failure is reported in its report (and
// returned), never thrown, but a stop (SIGINT / SIGTERM) ends the run.
CastEntry BuildCastTarget(const BuildOptions& options, const CastTarget& target, BuildTemplate& build_template,
                          SharedLandmarkDetector& detector) {
  CastEntry entry;
  entry.target = target;
  BuildOptions one = options;
  one.target_path = target.path;
  one.output = (fs::path(options.output_dir) / (target.name + "." + options.format)).string();
  one.report = (fs::path(options.output_dir) / (target.name + ".json")).string();
  entry.rig = one.output;
  entry.report = one.report;
  std::fprintf(stderr, "\n[%s] %s\n", target.name.c_str(), target.path.c_str());
  std::vector<BuildStage> stages;
  const auto start = std::chrono::steady_clock::now();
  try {
    entry.built = BuildTargetAndWrite(one, build_template, detector, std::nullopt, stages);
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& error) {
    entry.error = error.what();
    std::fprintf(stderr, "facerig: %s: %s (skipped)\n", target.path.c_str(), error.what());
    try {
      WriteFailureReport(one, entry.error, SecondsSince(start));
    } catch (const std::exception& report_error) {
      std::fprintf(stderr, "facerig: %s\n", report_error.what());
    }
  }
  entry.seconds = SecondsSince(start);
  return entry;
}

nlohmann::json SummaryTargets(const std::vector<CastEntry>& entries) {
  nlohmann::json list = nlohmann::json::array();
  for (const CastEntry& entry : entries) {
    nlohmann::json item = {{"name", entry.target.name},
                           {"target", entry.target.path},
                           {"status", entry.error.empty() ? "built" : "failed"},
                           {"report", entry.report},
                           {"seconds", entry.seconds}};
    if (entry.error.empty()) {
      item["rig"] = entry.rig;
      item["shapes"] = entry.built.shapes;
      item["residual_mean_percent"] = entry.built.residual_mean_percent;
    } else {
      item["error"] = entry.error;
    }
    list.push_back(item);
  }
  return list;
}

// The cast's summary: --json, and a few lines on stdout.
void ReportCast(const BuildOptions& options, const std::vector<CastEntry>& entries,
                const std::vector<BuildStage>& template_stages) {
  std::size_t built = 0;
  double built_seconds = 0.0;
  for (const CastEntry& entry : entries) {
    if (!entry.error.empty()) continue;
    ++built;
    built_seconds += entry.seconds;
  }
  const double template_seconds = TotalSeconds(template_stages);
  std::printf("cast: %zu of %zu targets built into %s (template %.2f s once, %.2f s per built target)\n", built,
              entries.size(), options.output_dir.c_str(), template_seconds,
              built > 0 ? built_seconds / static_cast<double>(built) : 0.0);
  for (const CastEntry& entry : entries) {
    if (!entry.error.empty()) std::printf("  failed: %s: %s\n", entry.target.path.c_str(), entry.error.c_str());
  }
  if (options.report.empty()) return;
  CommandReport summary{"build", {{"template", options.template_path}, {"template_info", options.template_info}}};
  for (const CastEntry& entry : entries) {
    summary.inputs.push_back({"target", entry.target.path});
    if (entry.error.empty()) summary.outputs.push_back({"rig", entry.rig});
    summary.outputs.push_back({"report", entry.report});
  }
  summary.result = {{"status", built == entries.size() ? "built" : "some failed"},
                    {"output_dir", options.output_dir},
                    {"built", built},
                    {"failed", entries.size() - built},
                    {"targets", SummaryTargets(entries)}};
  summary.timings = {{"load_template", StageSeconds(template_stages, "load template")},
                     {"prepare_template", StageSeconds(template_stages, "prepare template")},
                     {"targets", 0.0}};
  double total = template_seconds;
  for (const CastEntry& entry : entries) {
    summary.timings.back().second += entry.seconds;
    total += entry.seconds;
  }
  summary.timings.emplace_back("total", total);
  WriteCommandReport(options.report, summary);
}

int BuildCast(const BuildOptions& options) {
  CheckWritable({options.report});
  CheckWritable(options.output_dir);  // its parent exists: DIR is made when missing
  std::error_code error;
  if (!fs::is_directory(options.output_dir, error) && !fs::create_directory(options.output_dir, error)) {
    throw InvalidInputError("cannot make the --output-dir " + options.output_dir + ": " + error.message());
  }
  const std::vector<CastTarget> targets = ListTargets(options.targets);
  std::vector<BuildStage> template_stages;
  const std::unique_ptr<BuildTemplate> build_template =
      TimeStage(template_stages, "load template", [&] { return LoadBuildTemplate(options); });
  std::fprintf(stderr, "template %zu vertices, %zu shapes (%.2f s to load); %zu targets\n",
               build_template->rig.vertex_count(), build_template->rig.shape_count(),
               template_stages.back().seconds, targets.size());
  SharedLandmarkDetector detector(options, true);
  TimeStage(template_stages, "prepare template",
            [&] { PrepareBuildTemplate(options, *build_template, detector, true); });
  std::vector<CastEntry> entries;
  for (const CastTarget& target : targets) {
    entries.push_back(BuildCastTarget(options, target, *build_template, detector));
  }
  ReportCast(options, entries, template_stages);
  const bool all_built =
      std::all_of(entries.begin(), entries.end(), [](const CastEntry& entry) { return entry.error.empty(); });
  return all_built ? 0 : kSomeTargetsFailedExitCode;
}

}  // namespace

int RunBuildCast(const BuildOptions& options) {
  return RunWritingCommand([&options] { return BuildCast(options); });
}

}  // namespace facerig::cli
