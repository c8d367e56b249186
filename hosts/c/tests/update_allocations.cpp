// A per-frame update through the C ABI allocates nothing: 10 s at 60 fps of
// fr_character_update, fr_rig_blend and two blenders' fr_blender_blend (recomputed
// and blended recomputed normals) on the built-in head, speaking and with an
// emotion, counted by the replacement operator new that
// measure/allocation_counter.cpp puts in this program (libfacerig's own calls
// to operator new resolve to it). The blenders' positions, and the first's
// normals, equal fr_rig_blend's bit for bit every frame.
#include <cstdio>
#include <cstring>
#include <vector>

#include "facerig.h"
#include "measure/allocation_counter.h"

namespace {

const char kTrack[] =
    R"({"version": 1, "language": "en-us", "phonemes": [
      {"start": 0.00, "duration": 0.10, "symbol": "_:"}, {"start": 0.10, "duration": 0.12, "symbol": "a#"},
      {"start": 0.22, "duration": 0.04, "symbol": "p"},  {"start": 0.26, "duration": 0.12, "symbol": "A:"},
      {"start": 0.38, "duration": 0.03, "symbol": "b"},  {"start": 0.41, "duration": 0.12, "symbol": "A:"},
      {"start": 0.53, "duration": 0.05, "symbol": "m"},  {"start": 0.58, "duration": 0.15, "symbol": "A:"}]})";

int Fail(const char* what) {
  std::fprintf(stderr, "%s: %s\n", what, fr_last_error());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return Fail("usage: update_allocations HEAD.frig");
  fr_rig* rig = nullptr;
  fr_speech* speech = nullptr;
  fr_character* character = nullptr;
  fr_rig_info info{};
  if (fr_rig_load_file(argv[1], &rig) != FR_OK || fr_rig_get_info(rig, &info) != FR_OK) return Fail("load");
  if (fr_speech_load_track_bytes(kTrack, sizeof kTrack - 1, &speech) != FR_OK) return Fail("track");
  if (fr_character_create(rig, nullptr, &character) != FR_OK) return Fail("character");
  std::vector<float> weights(info.shape_count), positions(3 * info.vertex_count), normals(3 * info.vertex_count);
  std::vector<float> kept_positions(positions.size()), kept_normals(normals.size());
  std::vector<float> crowd_positions(positions.size()), crowd_normals(normals.size());
  fr_blender* blender = nullptr;
  fr_blender* crowd_blender = nullptr;
  if (fr_blender_create(rig, &blender) != FR_OK || fr_blender_create(rig, &crowd_blender) != FR_OK) {
    return Fail("blender");
  }
  std::size_t frames = 0, allocations = 0, differing_frames = 0;
  const auto same = [](const std::vector<float>& a, const std::vector<float>& b) {
    return std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
  };
  {
    facerig::test::AllocationCounter counter;
    for (int line = 0; line < 5; ++line) {
      if (fr_character_speak(character, speech, 2.0 * line) != FR_OK) return Fail("speak");
      if (fr_character_set_emotion(character, FR_EMOTION_JOY, line % 2 ? 0.0f : 0.8f) != FR_OK) return Fail("emotion");
      for (int frame = 0; frame < 120; ++frame, ++frames) {
        const double t = 2.0 * line + frame / 60.0;
        if (fr_character_update(character, t, weights.data(), weights.size()) != FR_OK) return Fail("update");
        if (fr_rig_blend(rig, weights.data(), weights.size(), FR_NORMALS_RECOMPUTE, positions.data(), normals.data(),
                         info.vertex_count) != FR_OK) {
          return Fail("blend");
        }
        if (fr_blender_blend(blender, weights.data(), weights.size(), FR_NORMALS_RECOMPUTE, kept_positions.data(),
                             kept_normals.data(), info.vertex_count) != FR_OK) {
          return Fail("blender blend");
        }
        differing_frames += !same(positions, kept_positions) || !same(normals, kept_normals);
        if (fr_blender_blend(crowd_blender, weights.data(), weights.size(), FR_NORMALS_BLEND_RECOMPUTED,
                             crowd_positions.data(), crowd_normals.data(), info.vertex_count) != FR_OK) {
          return Fail("blender blend, blended recomputed normals");
        }
        differing_frames += !same(positions, crowd_positions);
      }
    }
    allocations = counter.count();
  }
  // The counter counts: an allocation through the ABI shows.
  fr_speech* another = nullptr;
  std::size_t load_allocations = 0;
  {
    facerig::test::AllocationCounter counter;
    if (fr_speech_load_track_bytes(kTrack, sizeof kTrack - 1, &another) != FR_OK) return Fail("track");
    load_allocations = counter.count();
  }
  std::printf("%zu frames (update + blend and blender with normals): %zu allocations; loading a track: %zu;"
              " frames where the blender differs from fr_rig_blend: %zu\n",
              frames, allocations, load_allocations, differing_frames);
  fr_blender_release(blender);
  fr_blender_release(crowd_blender);
  fr_speech_release(another);
  fr_speech_release(speech);
  fr_character_release(character);
  fr_rig_release(rig);
  return allocations == 0 && load_allocations > 0 && differing_frames == 0 ? 0 : 1;
}
