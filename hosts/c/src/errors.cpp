// Version, status names and the per-thread message.
#include <cstring>

#include "boundary.h"

namespace {
thread_local char g_last_error[1024] = "";
}  // namespace

extern "C" {

uint32_t fr_abi_version(void) { return FR_ABI_VERSION; }

const char* fr_last_error(void) { return g_last_error; }

void fr_set_last_error(const char* message) {
  if (message == nullptr) {
    g_last_error[0] = '\0';
    return;
  }
  std::size_t n = std::strlen(message);
  if (n >= sizeof g_last_error) n = sizeof g_last_error - 1;
  std::memcpy(g_last_error, message, n);
  g_last_error[n] = '\0';
}

const char* fr_status_name(fr_status status) {
  switch (status) {
    case FR_OK: return "FR_OK";
    case FR_ERROR_INVALID_ARGUMENT: return "FR_ERROR_INVALID_ARGUMENT";
    case FR_ERROR_BUFFER_TOO_SMALL: return "FR_ERROR_BUFFER_TOO_SMALL";
    case FR_ERROR_NOT_FOUND: return "FR_ERROR_NOT_FOUND";
    case FR_ERROR_FILE: return "FR_ERROR_FILE";
    case FR_ERROR_FORMAT: return "FR_ERROR_FORMAT";
    case FR_ERROR_SPEECH: return "FR_ERROR_SPEECH";
    case FR_ERROR_STATE: return "FR_ERROR_STATE";
    case FR_ERROR_LIMIT: return "FR_ERROR_LIMIT";
    case FR_ERROR_OUT_OF_MEMORY: return "FR_ERROR_OUT_OF_MEMORY";
    case FR_ERROR_INTERNAL: return "FR_ERROR_INTERNAL";
    case FR_ERROR_CANCELLED: return "FR_ERROR_CANCELLED";
    case FR_ERROR_FAILED: return "FR_ERROR_FAILED";
  }
  return "unknown";
}

}  // extern "C"
