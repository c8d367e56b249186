// facerig-bench av-sync: the player on real recordings and their transcripts,
// headless, muxed with a plain ffmpeg command; the mouth's lag behind the
// sound measured from the frames' pixels and the WAV only (and again from the
// MP4 decoded back), with a track made 50 ms late as the control.
#pragma once

int RunAvSyncBenchmark(int argc, char** argv);
