// facerig-bench lipsync: lip-sync quality and cost over a corpus, measured on
// the geometry of a real rig (default ICT-FaceKit) with espeak-ng speech.
#pragma once

int RunLipsyncBenchmark(int argc, char** argv);
