// Splitting a text file into lines for the line-based readers (OBJ, MTL).
// Private to facerig::runtime_io.
#pragma once

#include <string_view>

namespace facerig {

// Calls `on_line` with each line of `text` in order, without its '\n' (a
// trailing '\r' stays for the caller to treat as space).
template <typename OnLine>
void ForEachLine(std::string_view text, OnLine&& on_line) {
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    on_line(text.substr(pos, end - pos));
    pos = end + 1;
  }
}

}  // namespace facerig
