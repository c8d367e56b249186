// facerig-bench align: transcript-to-recording alignment measured against
// exact truth (espeak-ng speech in one voice as the recording, another
// voice variant, pitch and rate as the reference), per language.
#pragma once

int RunAlignBenchmark(int argc, char** argv);
