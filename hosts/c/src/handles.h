// What the opaque handles of facerig.h hold. A rig's data is shared: each
// character keeps it alive, so a host may release its rig handle first.
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "facerig.h"
#include "facerig/runtime/alignment/streaming_alignment.h"
#include "facerig/runtime/audio/mouth_stream.h"
#include "facerig/runtime/blend_plan.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/speech/phoneme.h"

namespace facerig::capi {

// A rig and what characters need of it, built once. Never moves (the
// CharacterRig points at the Rig).
struct LoadedRig {
  explicit LoadedRig(Rig loaded) : rig(std::move(loaded)), characters(CharacterRig::Build(rig)) {}
  LoadedRig(const LoadedRig&) = delete;
  LoadedRig& operator=(const LoadedRig&) = delete;

  // Built by the first blender on this rig (the lock is at creation only).
  const BlendPlan& blend_plan() const {
    std::call_once(plan_once, [this] { plan.emplace(BlendPlan::Build(rig)); });
    return *plan;
  }

  Rig rig;
  CharacterRig characters;

 private:
  mutable std::once_flag plan_once;
  mutable std::optional<BlendPlan> plan;
};

}  // namespace facerig::capi

struct fr_rig {
  std::shared_ptr<const facerig::capi::LoadedRig> data;
};

struct fr_blender {
  explicit fr_blender(std::shared_ptr<const facerig::capi::LoadedRig> loaded)
      : rig(std::move(loaded)), state(rig->blend_plan()) {}

  std::shared_ptr<const facerig::capi::LoadedRig> rig;
  facerig::BlendState state;
};

struct fr_speech {
  facerig::SpeechLine line;    // phonemes; its int16 audio stays empty
  std::vector<float> samples;  // the audio, as given
  int sample_rate = 0;
};

struct fr_character {
  fr_character(std::shared_ptr<const facerig::capi::LoadedRig> loaded, const facerig::CharacterParams& params)
      : rig(std::move(loaded)), character(rig->characters, params) {}

  std::shared_ptr<const facerig::capi::LoadedRig> rig;
  facerig::Character character;
};

struct fr_audio_stream {
  std::optional<facerig::RoughMouthStream> rough;
  // Aligned mode: the reference's phonemes, re-timed as boundaries arrive;
  // each is final once the next one's start is known.
  std::unique_ptr<facerig::StreamingAligner> aligner;
  std::vector<facerig::Phoneme> reference;
  std::size_t timed = 0;       // reference phonemes with their recording start
  bool finished = false;
  std::vector<facerig::Phoneme> ready;  // final, not yet read
  std::size_t read = 0;                 // of `ready`
};

namespace facerig::capi {

// Conversions between fr_phoneme and facerig::Phoneme.
fr_phoneme ToC(const Phoneme& phoneme);
// Fails (FR_ERROR_INVALID_ARGUMENT) for a non-finite or negative time, or a
// symbol or language without its NUL.
fr_status FromC(const fr_phoneme& in, Phoneme* out);

}  // namespace facerig::capi
