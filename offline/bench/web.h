// facerig-bench web: the WebAssembly module (hosts/web/dist, run in node)
// against native C++ and the C ABI in one run: a character's update (and
// update + blend) per frame, and the bytes a page loads (.wasm + .mjs gzipped).
#pragma once

int RunWebBenchmark(int argc, char** argv);
