// Textured test assets the project makes itself: a UV-coded albedo (each
// pixel's colour says which UV it shows, so a test can check that UVs and
// pixels survived a command), and a shared ICT identity wearing it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace facerig::test {

// The colour the UV-coded albedo has at `uv` (OBJ convention, v up; u taken
// modulo 1): red = u, green = v, blue constant.
glm::u8vec4 UvCodedColour(glm::vec2 uv);
// That albedo as a `size` x `size` PNG (row 0 at the top, i.e. v = 1).
std::vector<std::uint8_t> UvCodedPng(std::uint32_t size);

// ../shared/data/ict-facekit/<identity>.obj copied into `folder` with an MTL
// whose face material (M_Face) shows albedo.png (the UV-coded albedo, 256
// pixels) and whose other materials are ICT's own. Returns the OBJ's path.
std::filesystem::path WriteTexturedIctIdentity(const std::filesystem::path& folder,
                                               const std::string& identity = "identity005");

}  // namespace facerig::test
