#include "boundary.h"

#include <charconv>
#include <new>
#include <stdexcept>

#include "facerig/runtime/alignment/dtw_align.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/speech/phoneme_source.h"

namespace facerig::capi {
namespace {

fr_status StatusOf(IoErrorKind kind) {
  switch (kind) {
    case IoErrorKind::kOpenFailed:
    case IoErrorKind::kWriteFailed: return FR_ERROR_FILE;
    default: return FR_ERROR_FORMAT;
  }
}

}  // namespace

fr_status Fail(fr_status status, std::string_view message) { return Fail(status, {message}); }

fr_status Fail(fr_status status, std::initializer_list<std::string_view> parts) {
  char joined[1024];
  std::size_t n = 0;
  for (std::string_view part : parts) {
    for (char ch : part) {
      if (n + 1 < sizeof joined) joined[n++] = ch;
    }
  }
  joined[n] = '\0';
  fr_set_last_error(joined);
  return status;
}

fr_status FailFromException(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const IoError& e) {
    return Fail(StatusOf(e.kind()), e.what());
  } catch (const SpeechError& e) {
    return Fail(FR_ERROR_SPEECH, e.what());
  } catch (const AlignmentError& e) {
    return Fail(FR_ERROR_SPEECH, e.what());
  } catch (const std::bad_alloc&) {
    return Fail(FR_ERROR_OUT_OF_MEMORY, "out of memory");
  } catch (const std::invalid_argument& e) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, e.what());
  } catch (const std::length_error& e) {
    return Fail(FR_ERROR_OUT_OF_MEMORY, {"out of memory: ", e.what()});
  } catch (const std::exception& e) {
    return Fail(FR_ERROR_INTERNAL, e.what());
  } catch (...) {
    return Fail(FR_ERROR_INTERNAL, "an unknown exception reached the C ABI");
  }
}

fr_status CopyString(std::string_view text, char* buffer, std::size_t capacity, std::size_t* needed) {
  if (needed) *needed = text.size() + 1;
  if (buffer == nullptr || capacity < text.size() + 1) {
    char size[24];
    return Fail(FR_ERROR_BUFFER_TOO_SMALL, {"the string needs a buffer of ", Number(text.size() + 1, size), " bytes"});
  }
  text.copy(buffer, text.size());
  buffer[text.size()] = '\0';
  return FR_OK;
}

fr_status CheckCapacity(std::size_t count, std::size_t capacity, std::size_t* needed, std::string_view what) {
  if (needed) *needed = count;
  if (capacity >= count) return FR_OK;
  char size[24], given[24];
  return Fail(FR_ERROR_BUFFER_TOO_SMALL,
              {what, " need room for ", Number(count, size), ", the buffer holds ", Number(capacity, given)});
}

std::string_view Number(std::size_t value, char (&buffer)[24]) {
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
  return std::string_view(buffer, static_cast<std::size_t>(end - buffer));
}

}  // namespace facerig::capi
