/* facerig_offline.h: the offline tools of the `facerig` command as calls, in
 * libfacerig_offline.so.0. C99. It holds the command-line tool's commands
 * and links facerig::offline (Eigen, OpenCV, dlib, CHOLMOD) and, in a build
 * with espeak-ng, espeak-ng: a program that links it is GPL as a whole (see
 * docs/licences.md). libfacerig alone stays MIT.
 *
 * Each call runs one command in-process with the options the command line
 * takes, given as a JSON object: a key is an option's long name without its
 * dashes ("template", "target", "frig", "obj-dir", "mode", or "o" for -o);
 * a string or number is its value, an array its values, true a flag, false
 * or null leaves it out; "inputs" holds the positional arguments (a string
 * or an array). E.g. fr_offline_photo("{\"inputs\": \"me.jpg\", \"o\":
 * \"me.glb\"}", ...). The outputs are written as the command writes them:
 * all together, or none (the previous files stay) on failure or cancel. The
 * command's JSON report (the schema of `facerig ... --json`) is kept for the
 * calling thread: fr_offline_report. The command may print to stdout and
 * stderr as on the command line, and while it writes, SIGINT and SIGTERM
 * stop it (its handlers replace the process's for the call).
 *
 * Returns FR_OK; FR_ERROR_INVALID_ARGUMENT for options the command refuses
 * (the message is the command line's); FR_ERROR_FILE or FR_ERROR_FORMAT for
 * unreadable or malformed inputs; FR_ERROR_FAILED when the command fails on
 * its input (no face found, ...); FR_ERROR_CANCELLED when `progress` asked
 * to stop. Calls may run on several threads at once; each blocks its thread
 * until the command is done. */
#ifndef FACERIG_OFFLINE_H
#define FACERIG_OFFLINE_H

#include "facerig.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Called on the calling thread as the command goes: the stage's name, and
 * `done` of `total` steps (total 0: unknown). Return 0 to go on, anything
 * else to stop the command (FR_ERROR_CANCELLED; nothing is written). May be
 * NULL. */
typedef int32_t (*fr_progress_fn)(void* user_data, const char* stage, uint64_t done, uint64_t total);

/* `facerig build`: a rig for a new face ("template", "target", "o", ...). */
FR_API fr_status fr_offline_build(const char* options_json, fr_progress_fn progress, void* user_data);

/* `facerig photo`: a talking head from one photograph ("inputs": IMAGE, "o", ...). */
FR_API fr_status fr_offline_photo(const char* options_json, fr_progress_fn progress, void* user_data);

/* `facerig default-head`: the built-in head into a folder ("inputs": OUT_DIR). */
FR_API fr_status fr_offline_default_head(const char* options_json, fr_progress_fn progress, void* user_data);

/* `facerig convert`: a rig from one format to another ("inputs": [IN, OUT]). */
FR_API fr_status fr_offline_convert(const char* options_json, fr_progress_fn progress, void* user_data);

/* The JSON report of the calling thread's last offline call that succeeded,
 * NUL-terminated, into `buffer`; *needed (optional) gets its size with the
 * NUL. "" before any. */
FR_API fr_status fr_offline_report(char* buffer, size_t capacity, size_t* needed);

#ifdef __cplusplus
}
#endif

#endif /* FACERIG_OFFLINE_H */
