/* A plain C99 program on facerig.h (-std=c99 -Wall -Wextra -Werror -pedantic):
 * loads the built-in head, speaks "a pa ba ma" from a phoneme track, reads
 * the weights at 60 fps, blends them, and checks that the lips close on every
 * p/b/m and open on the vowels; then that wrong calls return error codes.
 *
 * consumer HEAD.frig [REFERENCE.bin]: with REFERENCE, also writes one frame's
 * weights and blended positions there, the reference the Python binding's
 * test compares its blend with. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "facerig.h"

static int failures = 0;

#define CHECK(condition)                                                            \
  do {                                                                              \
    if (!(condition)) {                                                             \
      fprintf(stderr, "%s:%d: CHECK failed: %s (last error: %s)\n", __FILE__, __LINE__, \
              #condition, fr_last_error());                                         \
      ++failures;                                                                   \
    }                                                                               \
  } while (0)

/* "a pa ba ma" in espeak-ng's en-us names: open vowels around bilabials. */
static const char kTrack[] =
    "{\"format\": \"facerig-phoneme-track\", \"version\": 1, \"text\": \"a pa ba ma\", \"language\": \"en-us\",\n"
    " \"phonemes\": [\n"
    "  {\"start\": 0.00, \"duration\": 0.10, \"symbol\": \"_:\"},\n"
    "  {\"start\": 0.10, \"duration\": 0.12, \"symbol\": \"a#\", \"word_start\": true},\n"
    "  {\"start\": 0.22, \"duration\": 0.04, \"symbol\": \"p\", \"word_start\": true},\n"
    "  {\"start\": 0.26, \"duration\": 0.12, \"symbol\": \"A:\"},\n"
    "  {\"start\": 0.38, \"duration\": 0.03, \"symbol\": \"b\", \"word_start\": true},\n"
    "  {\"start\": 0.41, \"duration\": 0.12, \"symbol\": \"A:\"},\n"
    "  {\"start\": 0.53, \"duration\": 0.05, \"symbol\": \"m\", \"word_start\": true},\n"
    "  {\"start\": 0.58, \"duration\": 0.15, \"symbol\": \"A:\"},\n"
    "  {\"start\": 0.73, \"duration\": 0.20, \"symbol\": \"_:\"}]}\n";

/* The inner-lip contact on the midline: of the skin's midline vertices, the
 * nearest pair at rest of one that jawOpen carries (lower lip) and one it
 * leaves (upper lip). */
typedef struct LipPair {
  uint32_t upper, lower;
} LipPair;

static LipPair FindLips(const fr_rig* rig, const fr_rig_info* info, const float* neutral) {
  LipPair lips = {0, 0};
  fr_part_info skin;
  uint32_t jaw = 0;
  size_t n = info->vertex_count, i, j;
  float* weights = calloc(info->shape_count, sizeof(float));
  float* open = malloc(3 * n * sizeof(float));
  float* moved = malloc(n * sizeof(float));
  float most = 0.0f, best = 1e30f;
  CHECK(weights && open && moved);
  CHECK(fr_rig_part_info(rig, 0, &skin) == FR_OK);
  CHECK(fr_rig_find_shape(rig, "jawOpen", &jaw) == FR_OK);
  weights[jaw] = 1.0f;
  CHECK(fr_rig_blend(rig, weights, info->shape_count, FR_NORMALS_NONE, open, NULL, n) == FR_OK);
  for (i = 0; i < n; ++i) {
    float dx = open[3 * i] - neutral[3 * i], dy = open[3 * i + 1] - neutral[3 * i + 1];
    float dz = open[3 * i + 2] - neutral[3 * i + 2];
    moved[i] = sqrtf(dx * dx + dy * dy + dz * dz);
    if (moved[i] > most) most = moved[i];
  }
  for (i = skin.first_vertex; i < skin.first_vertex + skin.vertex_count; ++i) {
    if (fabsf(neutral[3 * i]) > 0.01f * info->bounding_diagonal || moved[i] < 0.5f * most) continue;
    for (j = skin.first_vertex; j < skin.first_vertex + skin.vertex_count; ++j) {
      float dx, dy, dz, d;
      if (fabsf(neutral[3 * j]) > 0.01f * info->bounding_diagonal || moved[j] > 0.1f * most) continue;
      dx = neutral[3 * i] - neutral[3 * j];
      dy = neutral[3 * i + 1] - neutral[3 * j + 1];
      dz = neutral[3 * i + 2] - neutral[3 * j + 2];
      d = dx * dx + dy * dy + dz * dz;
      if (d < best) {
        best = d;
        lips.upper = (uint32_t)j;
        lips.lower = (uint32_t)i;
      }
    }
  }
  free(weights);
  free(open);
  free(moved);
  return lips;
}

static float Distance(const float* p, uint32_t a, uint32_t b) {
  float dx = p[3 * a] - p[3 * b], dy = p[3 * a + 1] - p[3 * b + 1], dz = p[3 * a + 2] - p[3 * b + 2];
  return sqrtf(dx * dx + dy * dy + dz * dz);
}

/* Speaks the track at 60 fps; the lips close on each bilabial, open between. */
static void SpeakAndCheckLips(fr_rig* rig, const fr_rig_info* info, const float* neutral, const char* reference) {
  const double bilabial_start[3] = {0.22, 0.38, 0.53}, bilabial_end[3] = {0.26, 0.41, 0.58};
  float lowest[3] = {1e30f, 1e30f, 1e30f}, widest = 0.0f;
  LipPair lips = FindLips(rig, info, neutral);
  fr_character* character = NULL;
  fr_speech* speech = NULL;
  fr_character_state state;
  float* weights = malloc(info->shape_count * sizeof(float));
  float* positions = malloc(3 * (size_t)info->vertex_count * sizeof(float));
  int frame, k, saw_pp = 0;
  CHECK(weights && positions);
  printf("lips: upper %u, lower %u, %.3f apart at rest\n", lips.upper, lips.lower,
         (double)Distance(neutral, lips.upper, lips.lower));
  CHECK(fr_speech_load_track_bytes(kTrack, sizeof kTrack - 1, &speech) == FR_OK);
  CHECK(fr_character_create(rig, NULL, &character) == FR_OK);
  CHECK(fr_character_speak(character, speech, 0.0) == FR_OK);
  fr_speech_release(speech); /* the character keeps what it needs */
  for (frame = 0; frame < 60; ++frame) {
    const double t = frame / 60.0;
    float aperture;
    CHECK(fr_character_update(character, t, weights, info->shape_count) == FR_OK);
    CHECK(fr_rig_blend(rig, weights, info->shape_count, FR_NORMALS_NONE, positions, NULL, info->vertex_count) ==
          FR_OK);
    CHECK(fr_character_get_state(character, &state) == FR_OK);
    saw_pp = saw_pp || state.viseme == FR_VISEME_PP;
    aperture = Distance(positions, lips.upper, lips.lower);
    if (aperture > widest) widest = aperture;
    for (k = 0; k < 3; ++k) {
      /* A stop closes before its release: look from 60 ms before it. */
      if (t >= bilabial_start[k] - 0.06 && t <= bilabial_end[k] && aperture < lowest[k]) lowest[k] = aperture;
    }
    if (reference && frame == 20) { /* 0.33 s: mouth open on "A:" */
      FILE* out = fopen(reference, "wb");
      CHECK(out != NULL);
      if (out) {
        CHECK(fwrite(weights, sizeof(float), info->shape_count, out) == info->shape_count);
        CHECK(fwrite(positions, sizeof(float), 3 * (size_t)info->vertex_count, out) ==
              3 * (size_t)info->vertex_count);
        fclose(out);
      }
    }
  }
  printf("aperture: widest %.3f, on p %.3f, b %.3f, m %.3f\n", (double)widest, (double)lowest[0],
         (double)lowest[1], (double)lowest[2]);
  CHECK(widest > 0.5f); /* cm: the mouth opens on the vowels */
  for (k = 0; k < 3; ++k) CHECK(lowest[k] < 0.1f * widest);
  CHECK(saw_pp);
  fr_character_release(character);
  free(weights);
  free(positions);
}

/* Wrong calls return error codes with a message, never crash. */
static void CheckErrors(fr_rig* rig, const fr_rig_info* info, const char* head_path) {
  fr_rig* none = NULL;
  fr_character* character = NULL;
  fr_blender* blender = NULL;
  fr_phoneme phoneme;
  char name[4];
  size_t needed = 0;
  float weights[8];
  unsigned char truncated[64];
  FILE* head = fopen(head_path, "rb");
  uint32_t index = 0;

  CHECK(fr_rig_load_file("/nonexistent/head.glb", &none) == FR_ERROR_FILE && none == NULL);
  CHECK(strstr(fr_last_error(), "/nonexistent/head.glb") != NULL);
  CHECK(head != NULL);
  if (head) {
    CHECK(fread(truncated, 1, sizeof truncated, head) == sizeof truncated);
    fclose(head);
    CHECK(fr_rig_load_bytes(truncated, sizeof truncated, "head.frig", &none) == FR_ERROR_FORMAT);
    CHECK(strstr(fr_last_error(), "head.frig") != NULL);
  }
  CHECK(fr_rig_load_bytes("not a rig", 9, NULL, &none) == FR_ERROR_FORMAT);
  CHECK(fr_rig_get_info(NULL, NULL) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(fr_rig_shape_name(rig, 0, name, sizeof name, &needed) == FR_ERROR_BUFFER_TOO_SMALL);
  CHECK(needed == strlen("jawOpen") + 1);
  CHECK(fr_rig_shape_name(rig, info->shape_count, name, sizeof name, &needed) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(fr_rig_find_shape(rig, "noSuchShape", &index) == FR_ERROR_NOT_FOUND);
  CHECK(fr_character_create(rig, NULL, &character) == FR_OK);
  CHECK(fr_character_update(character, 0.0, weights, 8) == FR_ERROR_BUFFER_TOO_SMALL);
  CHECK(fr_character_update(character, NAN, weights, 8) != FR_OK);
  CHECK(fr_rig_blend(rig, weights, 8, FR_NORMALS_NONE, weights, NULL, 2) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(fr_blender_create(NULL, &blender) == FR_ERROR_INVALID_ARGUMENT && blender == NULL);
  CHECK(fr_blender_create(rig, &blender) == FR_OK);
  CHECK(fr_blender_blend(blender, weights, 8, FR_NORMALS_NONE, weights, NULL, 2) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(fr_last_error(), "weight_count") != NULL);
  CHECK(fr_blender_blend(NULL, weights, 8, FR_NORMALS_NONE, weights, NULL, 2) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(fr_blender_reset(blender) == FR_OK && fr_blender_reset(NULL) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(fr_rig_blend(rig, weights, 8, FR_NORMALS_BLEND_RECOMPUTED, weights, weights, 2) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(fr_last_error(), "needs a blender") != NULL);
  CHECK(fr_blender_blend(blender, weights, 8, (fr_normal_mode)4, weights, weights, 2) == FR_ERROR_INVALID_ARGUMENT);
  fr_blender_release(blender);
  fr_blender_release(NULL);
  memset(&phoneme, 0, sizeof phoneme);
  strcpy(phoneme.symbol, "p");
  CHECK(fr_character_push_phoneme(character, &phoneme) == FR_ERROR_STATE);
  CHECK(fr_character_begin_line(character, 0.0) == FR_OK);
  CHECK(fr_character_push_phoneme(character, &phoneme) == FR_OK);
  phoneme.start = -1.0;
  CHECK(fr_character_push_phoneme(character, &phoneme) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(fr_character_end_line(character) == FR_OK);
  CHECK(fr_character_set_emotion(character, (fr_emotion)42, 1.0f) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(fr_character_set_emotion(character, FR_EMOTION_JOY, 0.8f) == FR_OK);
  CHECK(fr_character_update(NULL, 0.0, weights, 8) == FR_ERROR_INVALID_ARGUMENT);
  CHECK(strcmp(fr_status_name(FR_ERROR_LIMIT), "FR_ERROR_LIMIT") == 0);
  fr_character_release(character);
  fr_character_release(NULL);
  fr_rig_release(NULL);
}

int main(int argc, char** argv) {
  fr_rig* rig = NULL;
  fr_rig_info info;
  float* neutral;
  if (argc < 2) {
    fprintf(stderr, "usage: consumer HEAD.frig [REFERENCE.bin]\n");
    return 2;
  }
  CHECK(fr_abi_version() >> 16 == FR_ABI_VERSION_MAJOR && (fr_abi_version() & 0xFFFF) >= FR_ABI_VERSION_MINOR);
  if (fr_rig_load_file(argv[1], &rig) != FR_OK) {
    fprintf(stderr, "cannot load %s: %s\n", argv[1], fr_last_error());
    return 1;
  }
  CHECK(fr_rig_get_info(rig, &info) == FR_OK);
  printf("%s: %u vertices, %u triangles, %u shapes, %u parts\n", argv[1], info.vertex_count, info.triangle_count,
         info.shape_count, info.part_count);
  neutral = malloc(3 * (size_t)info.vertex_count * sizeof(float));
  CHECK(neutral != NULL);
  CHECK(fr_rig_neutral(rig, neutral, NULL, info.vertex_count, NULL) == FR_OK);
  SpeakAndCheckLips(rig, &info, neutral, argc > 2 ? argv[2] : NULL);
  CheckErrors(rig, &info, argv[1]);
  free(neutral);
  fr_rig_release(rig);
  if (failures) fprintf(stderr, "%d checks failed\n", failures);
  return failures ? 1 : 0;
}
