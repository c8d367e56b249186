// The C ABI's load-from-bytes calls (libfacerig.so, facerig.h): a .glb or
// .frig through fr_rig_load_bytes and a phoneme track through
// fr_speech_load_track_bytes. Any input must come back as a status (no
// crash, no exception through the boundary, no sanitizer report); a rig that
// loads is then used as a host would: names, a blend, a character speaking.
#include <cstdint>
#include <cstring>
#include <vector>

#include "facerig.h"

namespace {

void UseRig(fr_rig* rig) {
  fr_rig_info info{};
  if (fr_rig_get_info(rig, &info) != FR_OK) __builtin_trap();
  char name[16];
  size_t needed = 0;
  for (uint32_t i = 0; i < info.shape_count && i < 4; ++i) fr_rig_shape_name(rig, i, name, sizeof name, &needed);
  std::vector<float> weights(info.shape_count, 0.5f), positions(3 * std::size_t{info.vertex_count});
  std::vector<float> normals(positions.size());
  if (fr_rig_blend(rig, weights.data(), weights.size(), FR_NORMALS_RECOMPUTE, positions.data(), normals.data(),
                   info.vertex_count) != FR_OK) {
    __builtin_trap();  // a loaded rig blends
  }
  fr_character* character = nullptr;
  if (fr_character_create(rig, nullptr, &character) != FR_OK) __builtin_trap();
  for (int frame = 0; frame < 3; ++frame) fr_character_update(character, frame / 60.0, weights.data(), weights.size());
  fr_character_release(character);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fr_rig* rig = nullptr;
  if (fr_rig_load_bytes(data, size, "input", &rig) == FR_OK) {
    UseRig(rig);
    fr_rig_release(rig);
  } else if (rig != nullptr || std::strlen(fr_last_error()) == 0) {
    __builtin_trap();  // a failure leaves no handle and says why
  }
  fr_speech* speech = nullptr;
  if (fr_speech_load_track_bytes(reinterpret_cast<const char*>(data), size, &speech) == FR_OK) {
    fr_phoneme phonemes[4];
    size_t needed = 0;
    fr_speech_phonemes(speech, phonemes, 4, &needed);
    fr_speech_release(speech);
  }
  return 0;
}
