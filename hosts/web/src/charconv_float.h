// std::to_chars / std::from_chars for float and double, which libc++ 13 (the
// one in Debian's emscripten 3.1.6) lacks; force-included in the WebAssembly
// build only (CMakeLists.txt), so the runtime's sources stay standard C++.
// Same contract as the standard's plain overloads: shortest text that reads
// back to the same value; from_chars takes no leading space, '+' or hex.
#pragma once

#include <charconv>

#if !defined(__cpp_lib_to_chars)
namespace std {
to_chars_result to_chars(char* first, char* last, float value);
to_chars_result to_chars(char* first, char* last, double value);
from_chars_result from_chars(const char* first, const char* last, float& value);
from_chars_result from_chars(const char* first, const char* last, double& value);
}  // namespace std
#endif
