// facerig-bench cast: a cast of random re-meshed ICT faces (as `facerig-bench
// build` makes them) and one target without a face, built by one `facerig
// build --output-dir` run against one `facerig build` per face (each loading
// and preparing the template again), in the same run: seconds per face,
// whether the rigs are byte-identical, and the bad face reported.
#pragma once

int RunCastBenchmark(int argc, char** argv);
