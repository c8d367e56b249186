#include "cli/names.h"

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "facerig/runtime/shape_names.h"

namespace facerig::cli {
namespace {

CLI::Validator ChoiceValidator(bool (*valid)(const std::string&), const char* choices) {
  return CLI::Validator(
      [valid, choices](const std::string& text) -> std::string {
        return valid(text) ? std::string() : "'" + text + "' is not " + choices;
      },
      choices);
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

}  // namespace

void AddShapeNamingOptions(CLI::App& app, StandardShapesOptions& options) {
  app.add_option_function<std::string>(
         "--names", [&options](const std::string& text) { options.names = *ParseShapeNaming(text); },
         "shape names written: arkit (Apple's 52, e.g. eyeBlinkLeft; default), ict (eyeBlink_L) or keep (the source's)")
      ->check(ChoiceValidator([](const std::string& text) { return ParseShapeNaming(text).has_value(); },
                              "arkit, ict or keep"));
  app.add_option_function<std::string>(
         "--visemes", [&options](const std::string& text) { options.visemes = *ParseVisemeTargets(text); },
         "viseme targets written: oculus (viseme_sil ... viseme_U, baked from the mouth shapes; default) or none")
      ->check(ChoiceValidator([](const std::string& text) { return ParseVisemeTargets(text).has_value(); },
                              "oculus or none"));
}

Rig NameShapesForWriting(const Rig& rig, const StandardShapesOptions& options, StandardShapesReport* report) {
  StandardShapesResult named = StandardizeShapes(rig, options);
  const StandardShapesReport& r = named.report;
  std::printf("shape names %s: %zu of %zu ARKit names", ToString(options.names), r.arkit_present,
              kArkitShapeCount);
  if (!r.merged.empty()) std::printf(" (%s from left and right halves)", JoinNames(r.merged).c_str());
  if (r.visemes_baked > 0) {
    std::printf("; %zu Oculus visemes baked\n", r.visemes_baked);
  } else {
    std::printf("; %zu viseme targets\n", r.viseme_targets);
  }
  std::fflush(stdout);
  std::vector<RigWarning> warnings;
  AddShapeNamingWarnings(r, warnings);
  for (const RigWarning& warning : warnings) std::fprintf(stderr, "facerig: warning: %s\n", warning.message.c_str());
  if (report) *report = r;
  return std::move(named.rig);
}

void AddShapeNamingWarnings(const StandardShapesReport& report, std::vector<RigWarning>& warnings) {
  if (!report.arkit_missing.empty()) {
    warnings.push_back({"missing_arkit_shapes", "the rig has no ARKit shape " + JoinNames(report.arkit_missing)});
  }
  for (const std::string& warning : report.warnings) warnings.push_back({"shape_names", warning});
}

void PrintShapeMatches(const Rig& rig) {
  const ShapeNameReport matches = MatchShapeNames(rig);
  std::size_t exact = 0;
  for (const ArkitShapeMatch& match : matches.matched) exact += match.kind == ShapeMatchKind::kExact ? 1 : 0;
  std::printf("\nARKit names: %zu of %zu matched (%zu spelled exactly), %zu viseme targets, %zu other shapes\n",
              matches.matched.size(), kArkitShapeCount, exact, matches.viseme_targets.size(), matches.other.size());
  for (const ArkitShapeMatch& match : matches.matched) {
    if (match.kind == ShapeMatchKind::kExact) continue;
    std::string shapes;
    for (std::size_t s : match.shapes) shapes += (shapes.empty() ? "" : " + ") + std::string(rig.shape_name(s));
    std::printf("  %-20.*s <- %s (%s)\n", static_cast<int>(match.arkit_name.size()), match.arkit_name.data(),
                shapes.c_str(), ToString(match.kind));
  }
  std::vector<std::string> missing(matches.missing.begin(), matches.missing.end());
  if (!missing.empty()) std::printf("  missing: %s\n", JoinNames(missing).c_str());
  std::fflush(stdout);
  std::vector<std::string> other;
  for (std::size_t s : matches.other) other.emplace_back(rig.shape_name(s));
  if (!other.empty()) std::printf("  other shapes: %s\n", JoinNames(other).c_str());
  std::fflush(stdout);
}

nlohmann::json ShapeMatchesJson(const Rig& rig) {
  const ShapeNameReport matches = MatchShapeNames(rig);
  nlohmann::json matched = nlohmann::json::array();
  for (const ArkitShapeMatch& match : matches.matched) {
    nlohmann::json shapes = nlohmann::json::array();
    for (std::size_t s : match.shapes) shapes.push_back(std::string(rig.shape_name(s)));
    matched.push_back({{"arkit", std::string(match.arkit_name)}, {"shapes", shapes}, {"match", ToString(match.kind)}});
  }
  nlohmann::json missing = nlohmann::json::array();
  for (std::string_view name : matches.missing) missing.push_back(std::string(name));
  const auto names_of = [&rig](const std::vector<std::size_t>& shapes) {
    nlohmann::json names = nlohmann::json::array();
    for (std::size_t s : shapes) names.push_back(std::string(rig.shape_name(s)));
    return names;
  };
  return {{"arkit_matched", matched},
          {"arkit_missing", missing},
          {"viseme_targets", names_of(matches.viseme_targets)},
          {"other", names_of(matches.other)}};
}

nlohmann::json ShapeNamesJson(const StandardShapesOptions& options, const StandardShapesReport& report) {
  return {{"names", ToString(options.names)},
          {"visemes", ToString(options.visemes)},
          {"arkit_present", report.arkit_present},
          {"arkit_missing", report.arkit_missing},
          {"merged_from_halves", report.merged},
          {"renamed", report.renamed},
          {"visemes_baked", report.visemes_baked},
          {"viseme_targets", report.viseme_targets},
          {"warnings", report.warnings}};
}

}  // namespace facerig::cli
