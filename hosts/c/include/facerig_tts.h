/* facerig_tts.h: text-to-speech and recorded-speech alignment with espeak-ng,
 * in libfacerig_espeak.so.0. espeak-ng is GPL-3: a program that links this
 * library takes on that licence (libfacerig alone stays MIT). C99.
 *
 * The calls return fr_status and report through fr_last_error() as in
 * facerig.h; the speech lines they make are fr_speech handles of
 * libfacerig, released with fr_speech_release.
 *
 * Threading: espeak-ng is one engine per process; these calls may come from
 * any thread and queue behind each other. The engine starts on the first
 * call (FR_ERROR_SPEECH, naming the folder tried, when its data is missing). */
#ifndef FACERIG_TTS_H
#define FACERIG_TTS_H

#include "facerig.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Speaks `text` with `voice` (a language such as "en-us", "de", "pt-br"; see
 * fr_tts_voices): on success *out_speech holds espeak-ng's audio (mono,
 * 22050 Hz) and its phonemes, timed exactly on that audio. Text over 16 KiB
 * is refused (split it into lines); empty text gives an empty line.
 * Errors: FR_ERROR_SPEECH (unknown voice, listing the available ones),
 * FR_ERROR_INVALID_ARGUMENT. */
FR_API fr_status fr_tts_synthesize(const char* text, const char* voice, fr_speech** out_speech);

/* Streaming synthesis callbacks, called on espeak-ng's worker thread while
 * fr_tts_synthesize_streaming blocks the caller's: the audio in chunks
 * (mono, in [-1, 1]) and each phoneme once its end is known, in time
 * order (a chunk comes after the phonemes completed within it). Return 0 to
 * go on, anything else to stop the line (FR_ERROR_CANCELLED). They must not
 * call fr_tts_* (the engine is busy with this line). */
typedef int32_t (*fr_tts_audio_fn)(void* user_data, const float* samples, size_t sample_count);
typedef int32_t (*fr_tts_phoneme_fn)(void* user_data, const fr_phoneme* phoneme);

/* Speaks `text` with `voice` as fr_tts_synthesize does, handing the audio
 * and phonemes to the callbacks as espeak-ng makes them (much faster than
 * real time): for a character that starts talking before the whole line is
 * synthesised (fr_character_push_phoneme). *sample_rate (optional) gets
 * the audio's rate (22050) before the first callback. Either callback may
 * be NULL. Errors as fr_tts_synthesize, and FR_ERROR_CANCELLED. */
FR_API fr_status fr_tts_synthesize_streaming(const char* text, const char* voice, int32_t* sample_rate,
                                             fr_tts_audio_fn on_audio, fr_tts_phoneme_fn on_phoneme,
                                             void* user_data);

/* Times the transcript's phonemes on a recording (mono samples in [-1, 1] at
 * `sample_rate`): the transcript is synthesised, the recording brought to
 * its rate, and the two aligned (dynamic time warping; no speech model, any
 * espeak-ng language). *out_speech holds the phonemes timed on the
 * recording, and the recording. FR_ERROR_SPEECH when the transcript gives no
 * speech or the alignment cannot run (audio over about 20 minutes). */
FR_API fr_status fr_tts_align(const float* samples, size_t sample_count, int32_t sample_rate,
                              const char* transcript, const char* voice, fr_speech** out_speech);

/* The voices' language names, sorted, one per line ("af\nam\n...\n"), into
 * `buffer` (NUL-terminated); *needed (optional) gets the size with the NUL. */
FR_API fr_status fr_tts_voices(char* buffer, size_t capacity, size_t* needed);

#ifdef __cplusplus
}
#endif

#endif /* FACERIG_TTS_H */
