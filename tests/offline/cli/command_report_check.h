// What every `facerig` command's --json report holds (tools/cli_report.h),
// whatever the command: checked by the tests of each command.
#pragma once

#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "cli/options.h"
#include "cli/report.h"

namespace facerig::test {

// The report of `command`: the shared fields with their types; a total time;
// the inputs and outputs each a role and a non-empty path.
inline void CheckCommandReport(const nlohmann::json& report, const std::string& command) {
  INFO(report.dump(2));
  CHECK(report["schema"] == cli::kReportSchema);
  CHECK(report["command"] == command);
  CHECK(report["version"] == cli::kVersion);
  for (const char* list : {"inputs", "outputs"}) {
    REQUIRE(report[list].is_array());
    for (const nlohmann::json& file : report[list]) {
      CHECK(!file["role"].get<std::string>().empty());
      CHECK(!file["path"].get<std::string>().empty());
    }
  }
  REQUIRE(report["warnings"].is_array());
  for (const nlohmann::json& warning : report["warnings"]) {
    CHECK(warning["code"].is_string());
    CHECK(warning["message"].is_string());
  }
  REQUIRE(report["timings"].is_object());
  CHECK(report["timings"]["total"].get<double>() >= 0.0);
  CHECK(report["result"].is_object());
}

}  // namespace facerig::test
