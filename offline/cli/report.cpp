#include "cli/report.h"

#include "cli/options.h"  // kVersion
#include "facerig/runtime/files/atomic_file.h"

namespace facerig::cli {
namespace {

nlohmann::ordered_json FileList(const std::vector<ReportFile>& files) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const ReportFile& file : files) {
    if (!file.path.empty()) list.push_back({{"role", file.role}, {"path", file.path}});
  }
  return list;
}

}  // namespace

nlohmann::ordered_json ToJson(const CommandReport& report) {
  nlohmann::ordered_json warnings = nlohmann::ordered_json::array();
  for (const RigWarning& warning : report.warnings) {
    warnings.push_back({{"code", warning.code}, {"message", warning.message}});
  }
  nlohmann::ordered_json timings = nlohmann::ordered_json::object();  // in the command's order
  for (const auto& [stage, seconds] : report.timings) timings[stage] = seconds;
  return {{"schema", kReportSchema},
          {"command", report.command},
          {"version", kVersion},
          {"inputs", FileList(report.inputs)},
          {"outputs", FileList(report.outputs)},
          {"warnings", warnings},
          {"timings", timings},
          {"result", nlohmann::ordered_json::parse(report.result.dump())}};
}

void WriteCommandReport(const std::filesystem::path& path, const CommandReport& report) {
  WriteFileAtomically(path, ToJson(report).dump(2) + "\n");
}

}  // namespace facerig::cli
