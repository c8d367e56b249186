/* facerig.h: the C ABI of facerig (libfacerig.so.0, MIT), C99.
 *
 * One prefix, fr_. Every object is an opaque handle made by a *_create or
 * *_load call and freed by its *_release call. Every call that can fail
 * returns an fr_status; on failure it writes nothing to its outputs (unless
 * said otherwise) and the calling thread's message says why (fr_last_error).
 * No call throws, exits or keeps a pointer the caller passed in. Buffers are
 * the caller's, with their size passed in: a call that fills a variable-size
 * buffer takes `capacity` and reports the size it needs through `needed`,
 * returning FR_ERROR_BUFFER_TOO_SMALL when `capacity` is less.
 *
 * Threading: a handle may be used from one thread at a time; different
 * handles from different threads at once. A rig is immutable once loaded, so
 * its const calls (fr_rig_*, except release) may run on many threads at once,
 * and many characters on many threads may share it.
 *
 * Times are seconds (double). Positions and normals are float triples (x, y,
 * z) per vertex, packed: 3 * vertex_count floats. Strings are UTF-8,
 * NUL-terminated.
 *
 * The GPL-3 text-to-speech part (espeak-ng) is a separate library,
 * libfacerig_espeak, declared in facerig_tts.h; the offline tools (rig
 * building, photo heads) another, libfacerig_offline, in facerig_offline.h. */
#ifndef FACERIG_H
#define FACERIG_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define FR_API __attribute__((visibility("default")))
#else
#define FR_API
#endif

/* ---- Version and errors ------------------------------------------------ */

/* A program built against FR_ABI_VERSION runs with a library whose
 * fr_abi_version() has the same major (high 16 bits, also the SONAME's
 * number) and an equal or higher minor (low 16 bits). */
#define FR_ABI_VERSION_MAJOR 0
#define FR_ABI_VERSION_MINOR 3
#define FR_ABI_VERSION ((FR_ABI_VERSION_MAJOR << 16) | FR_ABI_VERSION_MINOR)

typedef enum fr_status {
  FR_OK = 0,
  FR_ERROR_INVALID_ARGUMENT = 1, /* a NULL handle or pointer, a value out of range, NaN */
  FR_ERROR_BUFFER_TOO_SMALL = 2, /* the caller's buffer is smaller than `needed` */
  FR_ERROR_NOT_FOUND = 3,        /* no shape or part of that name */
  FR_ERROR_FILE = 4,             /* a file is missing, unreadable or not a regular file */
  FR_ERROR_FORMAT = 5,           /* malformed or truncated data (the message names the place) */
  FR_ERROR_SPEECH = 6,           /* speech synthesis or alignment failed */
  FR_ERROR_STATE = 7,            /* a call out of order (a phoneme pushed with no line begun) */
  FR_ERROR_LIMIT = 8,            /* a line longer than the character's key capacity */
  FR_ERROR_OUT_OF_MEMORY = 9,
  FR_ERROR_INTERNAL = 10,        /* a bug in facerig: please report the message */
  FR_ERROR_CANCELLED = 11,       /* the caller's progress callback asked to stop (facerig_offline.h) */
  FR_ERROR_FAILED = 12           /* an offline command failed on its input (the message says why) */
} fr_status;

/* The ABI version of the loaded library (FR_ABI_VERSION of its build).
 * Any thread. */
FR_API uint32_t fr_abi_version(void);

/* The calling thread's message about the last call that failed on it ("" if
 * none did). Set by every failing call, left alone by successful ones. The
 * pointer stays valid for the thread's life; the text until the next failing
 * call on the same thread. Never NULL. */
FR_API const char* fr_last_error(void);

/* Sets the calling thread's message (truncated to 1023 bytes), for libraries
 * and bindings layered on this ABI (libfacerig_espeak uses it); NULL clears
 * it. */
FR_API void fr_set_last_error(const char* message);

/* A static name for a status, e.g. "FR_ERROR_FORMAT"; "unknown" otherwise. */
FR_API const char* fr_status_name(fr_status status);

/* ---- Rigs ---------------------------------------------------------------- */

/* A loaded rig: neutral mesh plus named, sparse blend shapes. Immutable. */
typedef struct fr_rig fr_rig;

typedef enum fr_units { FR_UNITS_UNKNOWN = 0, FR_UNITS_MM = 1, FR_UNITS_CM = 2, FR_UNITS_M = 3 } fr_units;
typedef enum fr_up_axis { FR_UP_Y = 0, FR_UP_Z = 1 } fr_up_axis;

typedef struct fr_rig_info {
  uint32_t vertex_count;
  uint32_t triangle_count;
  uint32_t shape_count;
  uint32_t part_count;
  uint32_t has_uvs;           /* 1 when fr_rig_uvs has data */
  uint32_t has_normal_deltas; /* 1 when FR_NORMALS_BLEND_DELTAS can be used */
  uint32_t units;             /* fr_units */
  uint32_t up_axis;           /* fr_up_axis */
  float bounding_diagonal;    /* of the neutral, in the rig's units */
} fr_rig_info;

/* A named region of the mesh: a triangle range and the vertices it uses. */
typedef struct fr_part_info {
  uint32_t first_triangle;
  uint32_t triangle_count;
  uint32_t first_vertex;
  uint32_t vertex_count;
  int32_t material; /* index among the rig's materials; -1: none */
} fr_part_info;

/* Loads a .glb, .gltf, .frig or .obj file (format from the extension)
 * through facerig's hostile-input readers: regular files only, sizes checked
 * before allocating, glTF buffers only from the file's own folder.
 * On success *out_rig is a new rig the caller releases. Errors:
 * FR_ERROR_FILE, FR_ERROR_FORMAT (the message names the file and, where
 * known, the byte offset), FR_ERROR_INVALID_ARGUMENT. Any thread. */
FR_API fr_status fr_rig_load_file(const char* path, fr_rig** out_rig);

/* Loads a rig from the bytes of a .glb or .frig file (told apart by their
 * magic; a GLB may not name external files). `name` is only used in error
 * messages (NULL: "<memory>"). The bytes are copied as needed; the caller
 * keeps them. Errors as fr_rig_load_file. Any thread. */
FR_API fr_status fr_rig_load_bytes(const void* bytes, size_t size, const char* name, fr_rig** out_rig);

/* A rig from the caller's arrays, e.g. a mesh and its shape keys held by a
 * 3D application: `positions` (3 floats per vertex), `triangles` (3 vertex
 * indices each, counter-clockwise seen from outside) and `shape_count`
 * shapes, shape i named shape_names[i] (UTF-8, unique, not empty) with
 * dense position deltas: 3 * vertex_count floats per shape, shape after
 * shape in `deltas` (vertices moved less than 1e-7 of the bounding diagonal
 * are left out of the sparse shape). Normals are computed; no UVs, parts or
 * materials; units unknown, Y up. A character on it speaks with the shapes
 * its names give (ARKit and Oculus viseme names, facerig/runtime/
 * shape_names.h). Since ABI 0.2. Errors: FR_ERROR_INVALID_ARGUMENT (NULL,
 * NaN, an index out of range, an empty or repeated name: the message
 * names it). Any thread. */
FR_API fr_status fr_rig_create(const float* positions, size_t vertex_count, const uint32_t* triangles,
                               size_t triangle_count, const char* const* shape_names, const float* deltas,
                               size_t shape_count, fr_rig** out_rig);

/* Releases the caller's reference. Characters made from the rig keep it
 * alive until they are released too. NULL is ignored. Not while another
 * thread uses this handle. */
FR_API void fr_rig_release(fr_rig* rig);

/* Counts and properties of the rig. */
FR_API fr_status fr_rig_get_info(const fr_rig* rig, fr_rig_info* out_info);

/* The name of shape `index` (< shape_count) into `buffer`, NUL-terminated;
 * *needed (optional) gets its size with the NUL. */
FR_API fr_status fr_rig_shape_name(const fr_rig* rig, uint32_t index, char* buffer, size_t capacity,
                                   size_t* needed);

/* The index of the shape with exactly this name; FR_ERROR_NOT_FOUND if none. */
FR_API fr_status fr_rig_find_shape(const fr_rig* rig, const char* name, uint32_t* out_index);

/* Part `index` (< part_count): its ranges and its name (as fr_rig_shape_name). */
FR_API fr_status fr_rig_part_info(const fr_rig* rig, uint32_t index, fr_part_info* out_info);
FR_API fr_status fr_rig_part_name(const fr_rig* rig, uint32_t index, char* buffer, size_t capacity,
                                  size_t* needed);

/* The neutral mesh into caller buffers. `capacity` counts vertices
 * (triangles for fr_rig_triangles) and must be at least the rig's count;
 * *needed (optional) gets that count. fr_rig_neutral: positions and unit
 * normals, 3 floats per vertex, either pointer may be NULL. fr_rig_uvs: 2
 * floats per vertex, origin bottom-left (FR_ERROR_NOT_FOUND when the rig
 * has none). fr_rig_triangles: 3 vertex indices per triangle, counter-
 * clockwise seen from outside. */
FR_API fr_status fr_rig_neutral(const fr_rig* rig, float* positions, float* normals, size_t capacity,
                                size_t* needed);
FR_API fr_status fr_rig_uvs(const fr_rig* rig, float* uvs, size_t capacity, size_t* needed);
FR_API fr_status fr_rig_triangles(const fr_rig* rig, uint32_t* indices, size_t capacity, size_t* needed);

typedef enum fr_normal_mode {
  FR_NORMALS_NONE = 0,         /* positions only; `normals` may be NULL */
  FR_NORMALS_BLEND_DELTAS = 1, /* neutral normal + weighted normal deltas, renormalised */
  FR_NORMALS_RECOMPUTE = 2,    /* area-weighted normals of the blended positions */
  FR_NORMALS_BLEND_RECOMPUTED = 3, /* FR_NORMALS_RECOMPUTE's normals from each shape's (and pair of
                                     shapes') precomputed change of them: within a degree, at a
                                     fraction of the cost; fr_blender_blend only (ABI 0.3) */
  FR_NORMALS_FORCE_INT32 = 0x7FFFFFFF /* not a mode: makes every int a value of the type, so that a
                                         wrong one reaches the library's check (C++ range rules) */
} fr_normal_mode;

/* Per frame: positions = neutral + sum of weight[i] * shape i, over the
 * shapes whose weight is not 0. `weights` holds exactly shape_count finite
 * floats (e.g. from fr_character_update; may be NULL for a rig without
 * shapes); `positions` (and `normals` unless FR_NORMALS_NONE) hold
 * `vertex_capacity` >= vertex_count vertices (FR_ERROR_BUFFER_TOO_SMALL
 * otherwise; the count is in fr_rig_info).
 * Allocates nothing, takes no lock; many threads may blend one rig at once
 * into their own buffers. */
FR_API fr_status fr_rig_blend(const fr_rig* rig, const float* weights, size_t weight_count, fr_normal_mode mode,
                              float* positions, float* normals, size_t vertex_capacity);

/* A blender keeps one character's output buffers between frames and writes
 * only what moved since its last blend into them: the positions its shapes
 * moved then and now (the same bits as fr_rig_blend's), and with
 * FR_NORMALS_BLEND_RECOMPUTED the normals they turn. Since ABI 0.3. */
typedef struct fr_blender fr_blender;

/* One per pair of buffers (one per character), on `rig` (which it keeps
 * alive); creating allocates, once (the first blender on a rig also builds
 * what all its blenders share: 0.7 s for the built-in head). */
FR_API fr_status fr_blender_create(fr_rig* rig, fr_blender** out_blender);

/* NULL is ignored. */
FR_API void fr_blender_release(fr_blender* blender);

/* Per frame, as fr_rig_blend on the blender's rig, into the same buffers
 * each frame (other buffers, or another mode, make that blend write every
 * vertex). Write into them only through the blender, or call
 * fr_blender_reset afterwards. Allocates nothing, takes no lock; one thread
 * at a time per blender. */
FR_API fr_status fr_blender_blend(fr_blender* blender, const float* weights, size_t weight_count, fr_normal_mode mode,
                                  float* positions, float* normals, size_t vertex_capacity);

/* Forgets what the buffers hold: the next blend writes every vertex. */
FR_API fr_status fr_blender_reset(fr_blender* blender);

/* ---- Speech lines -------------------------------------------------------- */

#define FR_NAME_CAPACITY 16

/* A timed phoneme: the source's own symbol (espeak-ng names such as "aI",
 * "p", "_:" for a pause, or the rough mode's), the language it belongs to,
 * NUL-terminated (symbols at most 8 bytes, languages 15). */
typedef struct fr_phoneme {
  double start;    /* seconds from the start of the line's audio, >= 0 */
  double duration; /* seconds, >= 0 (may be 0) */
  char symbol[FR_NAME_CAPACITY];
  char language[FR_NAME_CAPACITY]; /* e.g. "en-us"; "" for the line's language */
  int32_t word_start;              /* 1 when the phoneme starts a word */
  int32_t reserved;                /* 0 */
} fr_phoneme;

/* A line to speak: timed phonemes and, optionally, its audio. Immutable. */
typedef struct fr_speech fr_speech;

/* A phoneme-track file (JSON "facerig-phoneme-track", version 1; see
 * runtime/io/include/facerig/runtime/io/phoneme_track_file.h) or its text.
 * Errors: FR_ERROR_FILE, FR_ERROR_FORMAT (with the JSON pointer and line of
 * the offending value). Any thread. */
FR_API fr_status fr_speech_load_track_file(const char* path, fr_speech** out_speech);
FR_API fr_status fr_speech_load_track_bytes(const char* json, size_t size, fr_speech** out_speech);

/* A line from phonemes (in time order) and optional mono audio in [-1, 1]
 * (`samples` may be NULL with sample_count 0 and sample_rate 0), e.g. another
 * TTS engine's timestamps. Both arrays are copied. */
FR_API fr_status fr_speech_create(const fr_phoneme* phonemes, size_t phoneme_count, const float* samples,
                                  size_t sample_count, int32_t sample_rate, fr_speech** out_speech);

/* The rough mode: a coarse mouth from a recording alone (loudness and
 * spectrum, no transcript); the line holds the audio. Sample rates 4-384 kHz. */
FR_API fr_status fr_speech_from_audio(const float* samples, size_t sample_count, int32_t sample_rate,
                                      fr_speech** out_speech);

/* A recording read from a file (WAV, FLAC, Ogg/Vorbis, AIFF, ... through
 * libsndfile; every channel averaged into one) as a line with that audio and
 * no phonemes: its samples, read with fr_speech_audio, are what
 * fr_speech_from_audio (the rough mode) and fr_tts_align take. Since ABI
 * 0.2. Errors: FR_ERROR_FILE (missing, unreadable, not a regular file),
 * FR_ERROR_FORMAT (not an audio format, no samples, truncated, over an
 * hour), each naming the file. Any thread. */
FR_API fr_status fr_speech_load_audio_file(const char* path, fr_speech** out_speech);

/* NULL is ignored. */
FR_API void fr_speech_release(fr_speech* speech);

/* The phonemes (capacity and *needed count phonemes) and the audio
 * (capacity and *needed count samples; *sample_rate, optional, gets its
 * rate, 0 when the line has no audio). */
FR_API fr_status fr_speech_phonemes(const fr_speech* speech, fr_phoneme* phonemes, size_t capacity,
                                    size_t* needed);
FR_API fr_status fr_speech_audio(const fr_speech* speech, float* samples, size_t capacity, size_t* needed,
                                 int32_t* sample_rate);

/* How well a recording fits the transcript it was aligned to. */
typedef struct fr_alignment_fit {
  double confidence; /* 1 - path distance / the reversed recording's: about 0 for other words or noise */
  double tempo;      /* the recording's speech over the reference's (far from 1: more or fewer words) */
  int32_t fits;      /* 1 under `facerig align`'s rule: confidence >= 0.06 and tempo within 0.5-2 */
  int32_t reserved;  /* 0 */
} fr_alignment_fit;

/* Times a reference line's phonemes on a recording of the same words: the
 * reference is the transcript as a synthesiser spoke it, with its audio and
 * exact phonemes (fr_speech_create with, e.g., espeak-ng's output in a web
 * page); `samples` is the recording, mono in [-1, 1] at the reference's
 * sample rate. The whole recording at once, as `facerig align` does (the
 * recording's pauses found and kept free of speech): more exact than an
 * aligned fr_audio_stream, which must commit as audio arrives.
 * *out_speech gets the reference's phonemes timed on the recording, and the
 * recording; *fit (optional) whether the two seem to match: the line is
 * returned either way, the caller decides. Since ABI 0.3. Errors:
 * FR_ERROR_INVALID_ARGUMENT (no samples, NaN, a rate other than the
 * reference's), FR_ERROR_SPEECH (the reference has no audio or no
 * phonemes, or the recording is over about 20 minutes). Any thread. */
FR_API fr_status fr_speech_align(const fr_speech* reference, const float* samples, size_t sample_count,
                                 int32_t sample_rate, fr_alignment_fit* fit, fr_speech** out_speech);

/* ---- Characters ---------------------------------------------------------- */

/* A talking character on a rig: speech -> coarticulated visemes -> weights,
 * with emotions, blinks and idle gaze, driven by the caller's clock (the
 * audio playback position). */
typedef struct fr_character fr_character;

typedef enum fr_emotion {
  FR_EMOTION_JOY = 0,
  FR_EMOTION_SADNESS = 1,
  FR_EMOTION_FEAR = 2,
  FR_EMOTION_ANGER = 3,
  FR_EMOTION_SURPRISE = 4,
  FR_EMOTION_DISGUST = 5,
  FR_EMOTION_FORCE_INT32 = 0x7FFFFFFF /* not an emotion: as FR_NORMALS_FORCE_INT32 */
} fr_emotion;

/* The Oculus visemes, in fr_character_state.viseme. */
typedef enum fr_viseme {
  FR_VISEME_SIL = 0, FR_VISEME_PP = 1, FR_VISEME_FF = 2, FR_VISEME_TH = 3, FR_VISEME_DD = 4,
  FR_VISEME_KK = 5, FR_VISEME_CH = 6, FR_VISEME_SS = 7, FR_VISEME_NN = 8, FR_VISEME_RR = 9,
  FR_VISEME_AA = 10, FR_VISEME_E = 11, FR_VISEME_IH = 12, FR_VISEME_OH = 13, FR_VISEME_OU = 14
} fr_viseme;

typedef struct fr_character_options {
  uint64_t seed;          /* blinks and gaze: the same seed, the same motion */
  float jaw_intensity;    /* JALI jaw, [0, 4]; 1 */
  float lip_intensity;    /* JALI lips, [0, 4]; 1 */
  uint32_t key_capacity;  /* viseme keys held at once, >= 8; 8192 (minutes of speech) */
  uint32_t blinks;        /* 1: blink; 0: lids open */
  uint32_t gaze;          /* 1: idle saccades; 0: eyes ahead */
} fr_character_options;

/* Fills *options with the defaults above. */
FR_API fr_status fr_character_default_options(fr_character_options* options);

/* A character on `rig` (which it keeps alive). `options` may be NULL for the
 * defaults. All its buffers are sized here: afterwards speaking and updating
 * allocate nothing. Any thread. */
FR_API fr_status fr_character_create(fr_rig* rig, const fr_character_options* options,
                                     fr_character** out_character);

/* NULL is ignored. */
FR_API void fr_character_release(fr_character* character);

/* Says a whole line whose time 0 is `start_time` on the character's clock,
 * replacing what it was saying. The speech may be released afterwards.
 * Errors: FR_ERROR_LIMIT (longer than key_capacity allows),
 * FR_ERROR_INVALID_ARGUMENT; nothing changes then. Allocates nothing. */
FR_API fr_status fr_character_speak(fr_character* character, const fr_speech* speech, double start_time);

/* Streaming: begin a line at `start_time` (replacing what is being said),
 * push its phonemes as they arrive (times from the line's start, starts never
 * going backwards; a phoneme shows once the next one or the end gives its
 * end), end it. FR_ERROR_STATE for a push or end with no line begun.
 * Allocate nothing. */
FR_API fr_status fr_character_begin_line(fr_character* character, double start_time);
FR_API fr_status fr_character_push_phoneme(fr_character* character, const fr_phoneme* phoneme);
FR_API fr_status fr_character_end_line(fr_character* character);

/* Stops speaking at once; the mouth relaxes over the next frames. */
FR_API fr_status fr_character_stop(fr_character* character);

/* Emotion target in [0, 1] (clamped), reached over the emotion's attack or
 * release time; several may be active. Layered on speech so that the lips
 * still close on p/b/m. */
FR_API fr_status fr_character_set_emotion(fr_character* character, fr_emotion emotion, float target);

/* Blinks and idle gaze on (1) or off (0). */
FR_API fr_status fr_character_set_behaviour(fr_character* character, int32_t blinks, int32_t gaze);

/* Per frame: the rig weights at `time` on the character's clock into
 * `weights`, which holds weight_capacity >= shape_count floats (the first
 * shape_count are written, each in [0, 1]; may be NULL for a rig without
 * shapes). Time may go backwards (a seek). FR_ERROR_INVALID_ARGUMENT for a
 * non-finite time (the previous weights are kept). Allocates nothing, takes
 * no lock. */
FR_API fr_status fr_character_update(fr_character* character, double time, float* weights, size_t weight_capacity);

/* What the last fr_character_update found (fr_character_get_state). */
typedef struct fr_character_state {
  int32_t talking;   /* 1 between the line's first and last key */
  int32_t at_pause;  /* 1 in a pause inside the line */
  int32_t viseme;    /* fr_viseme with the largest weight (FR_VISEME_SIL at rest) */
  float blink_left;  /* lid closure, [0, 1] */
  float blink_right;
  float gaze_x;      /* where the eyes look: + to the character's right, [-1, 1] */
  float gaze_y;      /* + up, [-0.6, 0.6] */
  char phoneme[FR_NAME_CAPACITY]; /* the phoneme under the clock, "" if none */
} fr_character_state;

/* Reads the state into *out_state. */
FR_API fr_status fr_character_get_state(const fr_character* character, fr_character_state* out_state);

/* ---- Audio streams --------------------------------------------------------- */

/* Phonemes from audio that arrives in chunks (a cloud TTS stream, a
 * microphone), to push into a character with fr_character_push_phoneme. Not
 * for a real-time thread: pushing may allocate. */
typedef struct fr_audio_stream fr_audio_stream;

/* The rough mode (no transcript): phonemes final within about 0.3 s of the
 * audio. Sample rates 4-384 kHz. */
FR_API fr_status fr_audio_stream_create_rough(int32_t sample_rate, fr_audio_stream** out_stream);

/* Streaming alignment to a transcript: `reference` is the transcript spoken
 * by a synthesiser, with its audio and exact phonemes (fr_tts_synthesize in
 * facerig_tts.h). The recording pushed must have the reference's sample
 * rate. The phonemes come out with the reference's symbols, timed on the
 * recording, final about 0.25 s after the audio. FR_ERROR_SPEECH for a
 * reference without audio or phonemes. */
FR_API fr_status fr_audio_stream_create_aligned(const fr_speech* reference, fr_audio_stream** out_stream);

/* Mono samples in [-1, 1]. */
FR_API fr_status fr_audio_stream_push(fr_audio_stream* stream, const float* samples, size_t sample_count);

/* The end of the audio: the remaining phonemes become readable. The stream
 * then takes a new line (rough mode) or no more audio (aligned). */
FR_API fr_status fr_audio_stream_finish(fr_audio_stream* stream);

/* Takes up to `capacity` of the phonemes made final so far, in time order;
 * *written gets how many. Call until it writes 0. */
FR_API fr_status fr_audio_stream_read(fr_audio_stream* stream, fr_phoneme* phonemes, size_t capacity,
                                      size_t* written);

/* NULL is ignored. */
FR_API void fr_audio_stream_release(fr_audio_stream* stream);

#ifdef __cplusplus
}
#endif

#endif /* FACERIG_H */
