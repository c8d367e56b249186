// facerig-bench register: landmark and registration measurements on random re-meshed ICT
// faces (tests/support/registration_targets.h): automatic landmark error and
// time per face, registration residuals, correspondence error and time of
// the ICT face + head region onto ~30k-vertex targets, and a million-vertex
// scan (time, peak memory), each printed against its target with published
// numbers as reference lines.
#pragma once

int RunRegisterBenchmark(int argc, char** argv);
