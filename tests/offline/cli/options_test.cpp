// The facerig command line (tools/cli_app.cpp, tools/cli_options.h), run
// in-process: --help on every subcommand prints the usage on stdout and exits 0,
// --version prints the project version, a bad value exits 2 naming the flag.
#include "cli/app.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "cli/options.h"
#include "support/command_runner.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

struct Outcome {
  int exit_code = -1;
  std::string output;  // stdout
  std::string errors;  // stderr
};

// RunFacerig with stdout captured too (CLI11 prints help and the version there).
Outcome RunWithStdout(const std::vector<std::string>& arguments) {
  test::CommandOutcome outcome;
  const std::string output = test::CaptureOutput(stdout, "cli_options_stdout", [&] {
    outcome = test::RunCommand(cli::RunFacerig, arguments);
  });
  return {outcome.exit_code, output, outcome.error_output};
}

using test::Contains;

}  // namespace

TEST_CASE("facerig --help and COMMAND --help print the usage on stdout and exit 0", "[cli]") {
  const Outcome top = RunWithStdout({"--help"});
  CHECK(top.exit_code == 0);
  CHECK(Contains(top.output, "Usage: facerig"));
  CHECK(top.errors.empty());
  for (const char* command :
       {"inspect", "convert", "landmarks", "register", "build", "photo", "average", "caricature", "morph",
        "default-head"}) {
    INFO(command);
    CHECK(Contains(top.output, command));  // listed
    const Outcome help = RunWithStdout({command, "--help"});
    CHECK(help.exit_code == 0);
    CHECK(Contains(help.output, std::string("Usage: facerig ") + command));
    CHECK(Contains(help.output, "--json"));  // every command reports in one schema (cli_report.h)
    CHECK(help.errors.empty());
  }
  const Outcome build = RunWithStdout({"build", "--help"});
  for (const char* flag : {"--template", "--target", "-o", "--frig", "--obj-dir", "--mode", "--landmarks", "--json",
                           "--units", "--template-topology", "--template-info", "--shape-predictor", "--no-contacts", "--no-eye-fit"}) {
    CHECK(Contains(build.output, flag));
  }
  const Outcome photo = RunWithStdout({"photo", "--help"});
  for (const char* flag : {"IMAGE", "-o", "--template", "--frig", "--obj-dir", "--json", "--debug-png", "--names",
                           "--visemes", "--shape-predictor", "--delight", "--no-delight", "--shading-fit",
                           "--no-shading-fit"}) {
    CHECK(Contains(photo.output, flag));
  }
  CHECK(Contains(photo.output, "(on by default)"));
  // CLI11's "--no-delight{false}" read as "off by default": no such marks on any command.
  for (const char* command : {"build", "photo", "average", "caricature"}) {
    INFO(command);
    CHECK_FALSE(Contains(RunWithStdout({command, "--help"}).output, "{false}"));
  }
}

TEST_CASE("facerig photo: --delight / --no-delight, and the off flags, set what they say", "[cli]") {
  bool value = true;
  CLI::App app("test", "test");
  cli::AddOnOffFlags(app, "delight", value, "divide the light out");
  app.parse(std::vector<std::string>{"--no-delight"});
  CHECK_FALSE(value);
  app.parse(std::vector<std::string>{"--delight"});
  CHECK(value);
  bool contacts = true;
  CLI::App build("test", "test");
  cli::AddOffFlag(build, "--no-contacts", contacts, "no contacts");
  build.parse(std::vector<std::string>{});
  CHECK(contacts);
  build.parse(std::vector<std::string>{"--no-contacts"});
  CHECK_FALSE(contacts);
}

TEST_CASE("facerig --version prints the project version", "[cli]") {
  const Outcome version = RunWithStdout({"--version"});
  CHECK(version.exit_code == 0);
  CHECK(version.output == std::string(FACERIG_VERSION) + "\n");
  CHECK(!std::string(cli::kVersion).empty());
}

TEST_CASE("facerig: a bad command line exits 2 with one error naming the flag and the value", "[cli]") {
  struct Case {
    std::vector<std::string> arguments;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{}, "facerig: a command is required"},
      {{"frobnicate"}, "not expected: frobnicate"},
      {{"inspect", "head.frig", "--units", "parsec"}, "facerig inspect: --units: 'parsec' is not mm, cm or m"},
      {{"convert", "a.obj", "b.frig", "--up", "x"}, "--up: 'x' is not y or z"},
      {{"convert", "a.obj", "b.frig", "--drop-threshold", "2"}, "--drop-threshold"},
      {{"inspect"}, "rig is required"},
      {{"build", "--template", "t", "--target", "m", "-o", "o.glb", "--mode", "foo"},
       "facerig build: --mode: 'foo' is not classic, identity or displacement"},
      {{"build", "--template", "t", "--target", "m", "-o", "o.glb", "--units", "parsec"}, "--units: 'parsec'"},
      {{"caricature", "--rig", "r", "--average", "a", "--factor", "abc", "-o", "o.frig"}, "--factor: 'abc' is not a number"},
      {{"default-head", "out", "--preview-size", "big"}, "--preview-size: 'big' is not a number"},
      // Out of range: refused, not clamped (was: raised to 64 / exit 1).
      {{"default-head", "out", "--preview-size", "10"}, "facerig default-head: --preview-size: 10 is outside [64, 4096]"},
      {{"caricature", "--rig", "r", "--average", "a", "--factor", "5", "-o", "o.frig"},
       "facerig caricature: --factor: 5 is outside [-1, 3]"},
      {{"landmarks", "m.obj", "-o"}, "-o"},
      {{"build", "--template", "t", "--target", "m", "-o", "o.glb", "--template-info", "no/such.json"},
       "--template-info: File does not exist: no/such.json"},
  };
  for (const Case& c : cases) {
    INFO(c.message);
    const Outcome outcome = RunWithStdout(c.arguments);
    CHECK(outcome.exit_code == 2);
    CHECK(Contains(outcome.errors, c.message));
    CHECK(Contains(outcome.errors, "--help"));  // where the usage is
    CHECK(outcome.output.empty());
  }
}

TEST_CASE("facerig: shared validators and helpers", "[cli]") {
  CHECK(cli::SplitCommaList("a,b,,c") == std::vector<std::string>{"a", "b", "c"});
  CHECK(cli::SplitCommaList("").empty());
  CHECK(cli::UnitsValidator()("cm").empty());
  CHECK_FALSE(cli::UnitsValidator()("unknown").empty());
  CHECK(cli::UpAxisValidator()("Z").empty());
  CHECK(cli::BuildModeValidator()("displacement").empty());
  CHECK_FALSE(cli::BuildModeValidator()("magic").empty());
}

}  // namespace facerig
