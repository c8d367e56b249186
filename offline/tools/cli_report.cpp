#include "cli_report.h"

#include "cli_options.h"  // kVersion
#include "facerig/runtime/io/atomic_file.h"

namespace facerig::cli {
namespace {

nlohmann::json FileList(const std::vector<ReportFile>& files) {
  nlohmann::json list = nlohmann::json::array();
  for (const ReportFile& file : files) {
    if (!file.path.empty()) list.push_back({{"role", file.role}, {"path", file.path}});
  }
  return list;
}

}  // namespace

nlohmann::json ToJson(const CommandReport& report) {
  nlohmann::json warnings = nlohmann::json::array();
  for (const RigWarning& warning : report.warnings) {
    warnings.push_back({{"code", warning.code}, {"message", warning.message}});
  }
  nlohmann::json timings = nlohmann::json::object();
  for (const auto& [stage, seconds] : report.timings) timings[stage] = seconds;
  return {{"schema", kReportSchema},
          {"command", report.command},
          {"version", kVersion},
          {"inputs", FileList(report.inputs)},
          {"outputs", FileList(report.outputs)},
          {"warnings", warnings},
          {"timings", timings},
          {"result", report.result}};
}

void WriteCommandReport(const std::filesystem::path& path, const CommandReport& report) {
  WriteFileAtomically(path, ToJson(report).dump(2) + "\n");
}

}  // namespace facerig::cli
