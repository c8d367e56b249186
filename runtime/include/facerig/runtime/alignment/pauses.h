// Pauses in a recording: stretches quiet enough and long enough that no
// phoneme should be stretched into them. Real recordings start and end with
// silence and pause between phrases; the warping crosses a pause at a fixed
// cost (dtw_align.h) and the aligned phonemes are kept out of it.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "facerig/runtime/speech/phoneme.h"

namespace facerig {

struct PauseParams {
  // Quiet: a frame's log energy below this share of the way from the quiet
  // end of the recording's energies (5th percentile) to the loud end (95th).
  double quiet_share = 0.25;
  // A quiet stretch touching the start or the end of the recording is a
  // pause from this long on; one inside it (between words, where stop
  // closures are quiet too, up to ~0.1 s) from the longer one.
  double min_edge_seconds = 0.15;
  double min_inner_seconds = 0.25;
  // Below this loudness range (natural log of energy, ~8.7 dB) nothing
  // stands out as speech: no pauses (noise, or speech without silence).
  double min_range = 2.0;
  // Loud (speech for sure): above this share of the same way, and at most
  // loud_depth below the loud end (natural log of energy, ~17 dB: the
  // quietest frames, e.g. silence an editor or a gate added, must not make a
  // breath loud). When quiet frames before the first loud frame make an edge
  // pause, all of it up to where the energy starts rising toward that frame is
  // the recording's leading silence, even where it is louder than the quiet
  // share (room tone after the silence); likewise after the last.
  double loud_share = 0.35;
  double loud_depth = 4.0;
};

// Frames [first, last] (inclusive) of one pause.
struct Pause {
  std::size_t first = 0, last = 0;
};

// The pauses in a sequence of per-frame log energies, `hop_seconds` apart,
// in order.
std::vector<Pause> FindPauses(std::span<const float> log_energy, double hop_seconds, const PauseParams& params = {});

// One flag per frame: quiet (below the quiet share, whatever the run's
// length); none when nothing stands out as speech.
std::vector<bool> QuietFrames(std::span<const float> log_energy, const PauseParams& params = {});

// One flag per frame: inside a pause.
std::vector<bool> PauseMask(std::span<const Pause> pauses, std::size_t frames);

// A pause phoneme (silence viseme) of a line in `line_language`: the only
// kind that may lie in a pause.
bool IsPausePhoneme(const Phoneme& phoneme, std::string_view line_language);

}  // namespace facerig
