// The edge of the C ABI: every fr_* call runs its body through Guard, which
// turns any C++ exception into an fr_status and this thread's message, so
// nothing is thrown across the boundary. Messages live in a fixed
// thread-local buffer (fr_last_error), so reporting allocates nothing.
#pragma once

#include <cstddef>
#include <exception>
#include <initializer_list>
#include <span>
#include <string_view>

#include "facerig.h"

namespace facerig::capi {

// Sets this thread's message (fr_set_last_error) and returns `status`.
fr_status Fail(fr_status status, std::string_view message);
// The same, for a message in parts, without allocating.
fr_status Fail(fr_status status, std::initializer_list<std::string_view> parts);
// A number for a message, written into `buffer`.
std::string_view Number(std::size_t value, char (&buffer)[24]);

// The status and message for the exception being handled (call in a catch).
fr_status FailFromException(std::exception_ptr error);

// A NULL check with the argument's name in the message.
#define FR_REQUIRE(pointer, name) \
  if ((pointer) == nullptr) return ::facerig::capi::Fail(FR_ERROR_INVALID_ARGUMENT, name " is NULL")

template <typename Body>
fr_status Guard(Body&& body) noexcept {
  try {
    return body();
  } catch (...) {
    return FailFromException(std::current_exception());
  }
}

// Copies `text` into a caller buffer as a NUL-terminated string.
fr_status CopyString(std::string_view text, char* buffer, std::size_t capacity, std::size_t* needed);

// `text` into a fixed char array, truncated, NUL-terminated.
template <std::size_t N>
void CopyName(std::string_view text, char (&out)[N]) {
  const std::size_t n = text.size() < N - 1 ? text.size() : N - 1;
  for (std::size_t i = 0; i < n; ++i) out[i] = text[i];
  for (std::size_t i = n; i < N; ++i) out[i] = '\0';
}

// The needed-size protocol for arrays: sets *needed (optional); OK when
// capacity >= count, else FR_ERROR_BUFFER_TOO_SMALL naming `what`.
fr_status CheckCapacity(std::size_t count, std::size_t capacity, std::size_t* needed, std::string_view what);

}  // namespace facerig::capi
