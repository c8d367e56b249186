// The command-line conventions of facerig, facerig-bench and facerig-player,
// on CLI11: --help prints to stdout and exits 0, --version prints the project
// version, a bad command line prints one line naming the flag and value to
// stderr and exits 2. Also the validators the programs share.
#pragma once

#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "facerig/offline/rigging/rig_build.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/rig.h"

namespace facerig::cli {

inline constexpr int kUsageExitCode = 2;
inline constexpr const char* kVersion = FACERIG_VERSION;

// A subcommand's work, set by its parse callback and run once the whole
// command line has parsed. Returns the exit code (0 ok, 1 failure).
using CommandBody = std::function<int()>;

// Adds --version to `app` (the top-level one: subcommands inherit none).
inline void AddVersionFlag(CLI::App& app) { app.set_version_flag("--version", kVersion, "print the version and exit"); }

// Parses argv into `app`. Returns the exit code when the program should stop
// here (0 after --help or --version, 2 after an error), else nullopt.
inline std::optional<int> ParseCommandLine(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help, std::cout, std::cerr);
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help, std::cout, std::cerr);
  } catch (const CLI::CallForVersion& version) {
    return app.exit(version, std::cout, std::cerr);
  } catch (const CLI::ParseError& error) {
    std::string command = app.get_name();  // "facerig build" when the error is in `build`
    const auto parsed = [](const CLI::App* sub) { return sub->parsed(); };
    for (const CLI::App* sub = &app; !sub->get_subcommands(parsed).empty();) {
      sub = sub->get_subcommands(parsed).front();
      command += " " + sub->get_name();
    }
    std::fprintf(stderr, "%s: %s\nRun '%s --help' for the options.\n", command.c_str(), error.what(),
                 command.c_str());
    return kUsageExitCode;
  }
}

// Parses like ParseCommandLine, for a program that needs one subcommand:
// naming an unknown one or none is a usage error (exit 2).
inline std::optional<int> ParseSubcommandLine(CLI::App& app, int argc, const char* const* argv) {
  if (const std::optional<int> exit_code = ParseCommandLine(app, argc, argv)) return exit_code;
  if (!app.get_subcommands().empty()) return std::nullopt;
  std::fprintf(stderr, "%s: a command is required\nRun '%s --help' for the commands.\n", app.get_name().c_str(),
               app.get_name().c_str());
  return kUsageExitCode;
}

// Validators: each error message names the bad value (CLI11 prefixes the flag).
inline CLI::Validator UnitsValidator() {
  return CLI::Validator(
      [](const std::string& text) -> std::string {
        const std::optional<Units> units = ParseUnits(text);
        return units && *units != Units::kUnknown ? std::string() : "'" + text + "' is not mm, cm or m";
      },
      "mm|cm|m");
}

// A value in [min_value, max_value], inclusive; the error names the value and
// the range as written: "--factor: 5 is outside [-1, 3]" (CLI11's Range
// prints "not in range -1.000000 to 3.000000").
template <typename T>
CLI::Validator InRange(T min_value, T max_value) {
  std::ostringstream range;
  range << "[" << min_value << ", " << max_value << "]";
  return CLI::Validator(
      [min_value, max_value, range = range.str()](std::string& text) -> std::string {
        T value{};
        if (!CLI::detail::lexical_cast(text, value)) return "'" + text + "' is not a number";
        return value >= min_value && value <= max_value ? std::string() : text + " is outside " + range;
      },
      range.str());
}

inline CLI::Validator UpAxisValidator() {
  return CLI::Validator(
      [](const std::string& text) -> std::string {
        return text == "y" || text == "Y" || text == "z" || text == "Z" ? std::string()
                                                                        : "'" + text + "' is not y or z";
      },
      "y|z");
}

// --NAME turning `value` off (it is on by default). Not CLI11's "!--NAME",
// which --help shows as "--NAME{false}", read as "off by default".
inline CLI::Option* AddOffFlag(CLI::App& app, const std::string& name, bool& value, const std::string& help) {
  return app.add_flag_callback(name, [&value] { value = false; }, help);
}

// --NAME and --no-NAME for a setting on by default (`value` stays as it is
// unless one is given; the last given wins).
inline void AddOnOffFlags(CLI::App& app, const std::string& name, bool& value, const std::string& help) {
  app.add_flag_callback("--" + name, [&value] { value = true; }, help + " (on by default)");
  AddOffFlag(app, "--no-" + name, value, "turn --" + name + " off");
}

// "a,b,,c" -> {a, b, c}.
inline std::vector<std::string> SplitCommaList(const std::string& text) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::size_t end = comma == std::string::npos ? text.size() : comma;
    if (end > start) items.push_back(text.substr(start, end - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

// --units mm|cm|m into `units`.
inline CLI::Option* AddUnitsOption(CLI::App& app, Units& units, const std::string& help) {
  return app
      .add_option_function<std::string>(
          "--units", [&units](const std::string& text) { units = *ParseUnits(text); }, help)
      ->check(UnitsValidator());
}

// --up y|z into `up_axis`.
inline CLI::Option* AddUpAxisOption(CLI::App& app, UpAxis& up_axis, const std::string& help) {
  return app
      .add_option_function<std::string>(
          "--up", [&up_axis](const std::string& text) { up_axis = text == "z" || text == "Z" ? UpAxis::kZ : UpAxis::kY; },
          help)
      ->check(UpAxisValidator());
}

// A comma-separated list option (`--shapes a,b,c`) into `items`.
inline CLI::Option* AddCommaListOption(CLI::App& app, const std::string& name, std::vector<std::string>& items,
                                       const std::string& help) {
  return app.add_option_function<std::string>(
      name, [&items](const std::string& text) { items = SplitCommaList(text); }, help);
}

inline CLI::Validator BuildModeValidator() {
  return CLI::Validator(
      [](const std::string& text) -> std::string {
        return ParseBuildMode(text) ? std::string() : "'" + text + "' is not classic, identity or displacement";
      },
      "classic|identity|displacement");
}

// --mode classic|identity|displacement into `mode`.
inline CLI::Option* AddBuildModeOption(CLI::App& app, BuildMode& mode) {
  return app
      .add_option_function<std::string>(
          "--mode", [&mode](const std::string& text) { mode = *ParseBuildMode(text); },
          "transfer: deformation transfer (classic, identity-gradient) or displacement matrices")
      ->check(BuildModeValidator());
}

}  // namespace facerig::cli
