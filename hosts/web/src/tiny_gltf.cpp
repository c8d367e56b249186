// tinygltf's implementation, compiled into the module (Debian ships it as a
// shared library for the host only). Images stay encoded: the runtime's
// readers install their own image callback, so stb is not needed. No file
// system (TINYGLTF_NO_FS, set for the whole module in CMakeLists.txt): the
// runtime's reader installs its own file callbacks, and a page has no files.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>  // named by tinygltf's file writers even without a file system (never reached)
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

// tinygltf writes its error messages with std::stringstream, and one use of a
// std::stringstream links libc++'s whole locale (every facet for char and
// wchar_t: about a tenth of the module). Here it gets this string builder
// instead, which formats what tinygltf streams (text, integers, doubles,
// std::endl) as a default-formatted stream would. The standard headers are
// all included above, so the macro renames tinygltf's uses only.
namespace facerig_web {
class MessageStream {
 public:
  MessageStream& operator<<(std::string_view text) {
    text_ += text;
    return *this;
  }
  MessageStream& operator<<(const char* text) { return *this << std::string_view(text); }
  MessageStream& operator<<(const std::string& text) { return *this << std::string_view(text); }
  MessageStream& operator<<(char c) {
    text_ += c;
    return *this;
  }
  template <std::integral Integer>
  MessageStream& operator<<(Integer value) {
    text_ += std::to_string(value);
    return *this;
  }
  MessageStream& operator<<(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return *this << std::string_view(text);
  }
  // std::endl, the only manipulator tinygltf streams.
  MessageStream& operator<<(std::ostream& (*)(std::ostream&)) { return *this << '\n'; }
  std::string str() const { return text_; }

 private:
  std::string text_;
};
}  // namespace facerig_web

namespace std {
using facerig_web_message_stream = ::facerig_web::MessageStream;
}
#define stringstream facerig_web_message_stream
#include <tiny_gltf.h>
#undef stringstream

// tinygltf's default image callbacks, which it names even when stb is left
// out: facerig's reader installs its own loader (images stay encoded) and
// its writer embeds encoded images, so these only refuse.
namespace tinygltf {
bool LoadImageData(Image*, const int, std::string* err, std::string*, int, int, const unsigned char*, int, void*) {
  if (err) *err += "facerig (WebAssembly): no built-in image decoder\n";
  return false;
}
bool WriteImageData(const std::string*, const std::string*, const Image*, bool, std::string*, void*) {
  return false;
}
}  // namespace tinygltf
