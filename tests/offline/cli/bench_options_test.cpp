// facerig-bench's command lines: an out-of-range value is refused (exit 2,
// naming the option and the value), never clamped to a different run.
#include <string>
#include <utility>

#include <catch2/catch.hpp>

#include "support/command_runner.h"

TEST_CASE("facerig-bench: out-of-range values exit 2 naming the option and the value", "[cli]") {
  for (const auto& [arguments, message] :
       {std::pair<std::string, std::string>{"crowd 0", "facerig-bench crowd: count: 0 is outside [1, 1000000]"},
        {"crowd 5 --frames 3", "--frames: 3 is outside [10, 1000000]"},
        {"register --faces 0", "--faces: 0 is outside [1, 1000000]"},
        {"cast --faces 0", "--faces: 0 is outside [1, 1000]"},
        {"proportions --faces 1", "--faces: 1 is outside [2, 100000]"},
        {"transfer --threads 0", "--threads: 0 is outside [1, 1024]"},
        {"av-sync --fps 0", "--fps: 0 is outside [1, 1000]"},
        {"abi --frames 3", "--frames: 3 is outside [100, 10000000]"},
        {"web --repeats 0", "--repeats: 0 is outside [1, 100]"}}) {
    INFO(arguments);
    std::string output;
    CHECK(facerig::test::RunShell("'" FACERIG_BENCH_EXE "' " + arguments, &output) == 2);
    INFO(output);
    CHECK(output.find(message) != std::string::npos);
  }
}
