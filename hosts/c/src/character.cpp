// Characters: speech, streamed phonemes, emotions, behaviour, the per-frame
// update into the caller's weights (no allocation).
#include <algorithm>
#include <cmath>

#include "boundary.h"
#include "handles.h"

namespace facerig::capi {
namespace {

fr_status FromCharacter(CharacterError error) {
  switch (error) {
    case CharacterError::kNone: return FR_OK;
    case CharacterError::kTooManyKeys: return Fail(FR_ERROR_LIMIT, ToString(error));
    case CharacterError::kNoOpenLine: return Fail(FR_ERROR_STATE, ToString(error));
    case CharacterError::kNonFiniteTime:
    case CharacterError::kInvalidPhoneme:
    case CharacterError::kInvalidKey: return Fail(FR_ERROR_INVALID_ARGUMENT, ToString(error));
  }
  return Fail(FR_ERROR_INTERNAL, "unknown character error");
}

fr_status ParamsFromOptions(const fr_character_options& options, CharacterParams* params) {
  const auto intensity_ok = [](float v) { return std::isfinite(v) && v >= 0.0f && v <= 4.0f; };
  if (!intensity_ok(options.jaw_intensity) || !intensity_ok(options.lip_intensity)) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, "jaw_intensity and lip_intensity must lie in [0, 4]");
  }
  if (options.key_capacity < 8) return Fail(FR_ERROR_INVALID_ARGUMENT, "key_capacity must be at least 8");
  params->seed = options.seed;
  params->jaw_intensity = options.jaw_intensity;
  params->lip_intensity = options.lip_intensity;
  params->key_capacity = options.key_capacity;
  params->gaze.enabled = options.gaze != 0;
  return FR_OK;
}

}  // namespace
}  // namespace facerig::capi

using namespace facerig::capi;
using facerig::Seconds;

extern "C" {

fr_status fr_character_default_options(fr_character_options* options) {
  FR_REQUIRE(options, "options");
  const facerig::CharacterParams defaults;
  *options = {defaults.seed, defaults.jaw_intensity, defaults.lip_intensity,
              static_cast<uint32_t>(defaults.key_capacity), 1, 1};
  return FR_OK;
}

fr_status fr_character_create(fr_rig* rig, const fr_character_options* options, fr_character** out_character) {
  return Guard([&] {
    FR_REQUIRE(out_character, "out_character");
    *out_character = nullptr;
    FR_REQUIRE(rig, "rig");
    fr_character_options chosen;
    fr_character_default_options(&chosen);
    if (options) chosen = *options;
    facerig::CharacterParams params;
    if (const fr_status s = ParamsFromOptions(chosen, &params); s != FR_OK) return s;
    auto character = std::make_unique<fr_character>(rig->data, params);
    character->character.SetBlinking(chosen.blinks != 0);
    *out_character = character.release();
    return FR_OK;
  });
}

void fr_character_release(fr_character* character) { delete character; }

fr_status fr_character_speak(fr_character* character, const fr_speech* speech, double start_time) {
  return Guard([&] {
    FR_REQUIRE(character, "character");
    FR_REQUIRE(speech, "speech");
    return FromCharacter(character->character.Speak(speech->line.phonemes, Seconds(start_time)));
  });
}

fr_status fr_character_begin_line(fr_character* character, double start_time) {
  return Guard([&] {
    FR_REQUIRE(character, "character");
    return FromCharacter(character->character.BeginLine(Seconds(start_time)));
  });
}

fr_status fr_character_push_phoneme(fr_character* character, const fr_phoneme* phoneme) {
  return Guard([&] {
    FR_REQUIRE(character, "character");
    FR_REQUIRE(phoneme, "phoneme");
    facerig::Phoneme converted;
    if (const fr_status s = FromC(*phoneme, &converted); s != FR_OK) return s;
    return FromCharacter(character->character.PushPhoneme(converted));
  });
}

fr_status fr_character_end_line(fr_character* character) {
  return Guard([&] {
    FR_REQUIRE(character, "character");
    return FromCharacter(character->character.EndLine());
  });
}

fr_status fr_character_stop(fr_character* character) {
  FR_REQUIRE(character, "character");
  character->character.StopSpeaking();
  return FR_OK;
}

fr_status fr_character_set_emotion(fr_character* character, fr_emotion emotion, float target) {
  FR_REQUIRE(character, "character");
  if (const int e = static_cast<int>(emotion); e < FR_EMOTION_JOY || e > FR_EMOTION_DISGUST) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, "emotion is not an fr_emotion");
  }
  if (std::isnan(target)) return Fail(FR_ERROR_INVALID_ARGUMENT, "the emotion target is NaN");
  character->character.SetEmotion(static_cast<facerig::Emotion>(emotion), target);
  return FR_OK;
}

fr_status fr_character_set_behaviour(fr_character* character, int32_t blinks, int32_t gaze) {
  FR_REQUIRE(character, "character");
  character->character.SetBlinking(blinks != 0);
  character->character.SetGazing(gaze != 0);
  return FR_OK;
}

fr_status fr_character_update(fr_character* character, double time, float* weights, size_t weight_capacity) {
  return Guard([&] {
    FR_REQUIRE(character, "character");
    facerig::Character& c = character->character;
    const std::size_t count = character->rig->rig.shape_count();
    if (weights == nullptr && count > 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "weights is NULL");
    if (const fr_status s = CheckCapacity(count, weight_capacity, nullptr, "weights"); s != FR_OK) return s;
    if (const fr_status s = FromCharacter(c.Update(Seconds(time))); s != FR_OK) return s;
    std::copy(c.weights().begin(), c.weights().end(), weights);
    return FR_OK;
  });
}

fr_status fr_character_get_state(const fr_character* character, fr_character_state* out_state) {
  FR_REQUIRE(character, "character");
  FR_REQUIRE(out_state, "out_state");
  const facerig::Character& c = character->character;
  fr_character_state state{};
  state.talking = c.talking() ? 1 : 0;
  state.at_pause = c.at_pause() ? 1 : 0;
  state.viseme = static_cast<int32_t>(c.dominant_viseme());
  state.blink_left = c.blink_left();
  state.blink_right = c.blink_right();
  state.gaze_x = c.gaze().x;
  state.gaze_y = c.gaze().y;
  if (const facerig::Phoneme* phoneme = c.current_phoneme()) CopyName(phoneme->symbol.view(), state.phoneme);
  *out_state = state;
  return FR_OK;
}

}  // extern "C"
