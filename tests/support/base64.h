// Base64 (RFC 4648, standard alphabet, '=' padding) for the data: URIs that
// tests write into glTF files by hand, without the library under test.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace facerig::test {

std::string Base64Encode(std::span<const unsigned char> data);

// Decodes up to the first '=' or character outside the alphabet; no validation.
std::vector<unsigned char> Base64Decode(std::string_view text);

}  // namespace facerig::test
