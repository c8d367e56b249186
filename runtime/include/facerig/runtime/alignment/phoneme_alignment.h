// Lip-sync for recorded speech: a synthetic rendition of the transcript (any
// PhonemeSource that returns audio with its phonemes, e.g. espeak-ng) is
// warped onto the recording, and its exact phoneme boundaries are carried
// across the warping path. Language-independent; needs no speech model.
#pragma once

#include <cstddef>
#include <span>

#include "facerig/runtime/audio/features.h"
#include "facerig/runtime/alignment/dtw_align.h"
#include "facerig/runtime/alignment/pauses.h"
#include "facerig/runtime/speech/phoneme.h"

namespace facerig {

struct PhonemeAlignmentParams {
  AudioFeatureParams features;
  // Half-width of the warping band around the guide (the straight line from
  // the start of speech in one to that in the other, and likewise their ends):
  // the larger of the two, capped. Tempo differences between the voices must
  // stay inside it.
  double band_radius_seconds = 0.6;
  double band_radius_fraction = 0.25;  // of the recording's duration
  double max_band_radius_seconds = 8.0;
  // Memory bound: one byte per band cell. At the defaults 10 s of audio need
  // ~0.5e6 cells, a minute ~10e6, and past 32 s (the band at its cap) each
  // further second ~0.16e6: the default admits about 20 minutes (200 MB).
  std::size_t max_cells = std::size_t{200} << 20;
  // The recording's pauses (silence at its ends, long ones inside) are
  // crossed at a fixed cost and kept free of phonemes other than pauses;
  // false: every frame is warped like speech (the behaviour before pauses).
  bool pauses = true;
  PauseParams pause_params;
};

struct PhonemeAlignment {
  // The reference's text, language and phonemes, timed on the recording
  // (starts non-decreasing, each duration up to the next start); no audio.
  SpeechLine line;
  double cost = 0.0;  // mean feature distance along the path (lower: closer match)
  std::size_t pauses = 0;  // pauses found in the recording (0 when params.pauses is false)
  // How well the transcript fits the recording: 1 - the mean feature distance
  // along the path / the same for the recording reversed in time (its frames
  // alike, their order not speech that the transcript describes). About 0
  // for a transcript of other words or for noise; higher the better the fit.
  double confidence = 0.0;
  // The recording's speech (first to last loud frame) over the reference's:
  // far from 1, the transcript says more or less than the recording.
  double tempo = 1.0;
};

// Aligns `reference` (audio + exactly timed phonemes of the transcript) with
// `recording`, mono samples at reference.sample_rate. Phonemes the reference
// places before its speech or after it map to the recording's silence; no
// other phoneme overlaps a pause of the recording (one that would is cut at
// its edge, and a pause phoneme next to it takes it over). A
// /p b m/ the warping squeezed to no time is placed on the recording's own
// release instead (release_landmark.h).
// \throw AlignmentError when the reference has no audio or no phonemes, the
// recording is empty, or the band needs more than params.max_cells cells
// (split long audio into lines); std::invalid_argument for bad params.
PhonemeAlignment AlignPhonemesToRecording(const SpeechLine& reference, std::span<const float> recording,
                                          const PhonemeAlignmentParams& params = {});

// The time on the recording of a reference time, along `path` (rows: the
// reference's frames, columns: the recording's). Both feature sets must be
// those the path was computed from.
double MapReferenceTime(double reference_seconds, const DtwPath& path, const AudioFeatures& reference,
                        const AudioFeatures& recording);

}  // namespace facerig
