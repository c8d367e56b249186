#include "textured_assets.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "test_images.h"
#include "test_meshes.h"

namespace facerig::test {
namespace {

std::string ReadWhole(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteWhole(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// ICT's material library with M_Face's block textured.
std::string TexturedMaterials(const std::string& ict_mtl) {
  std::istringstream in(ict_mtl);
  std::string out, line;
  bool in_face = false;
  while (std::getline(in, line)) {
    if (line.rfind("newmtl ", 0) == 0) in_face = line == "newmtl M_Face" || line == "newmtl M_Face\r";
    if (in_face && line.rfind("Kd ", 0) == 0) line = "Kd 1.0 1.0 1.0\nmap_Kd albedo.png";
    out += line + "\n";
  }
  return out;
}

}  // namespace

glm::u8vec4 UvCodedColour(glm::vec2 uv) {
  const float u = uv.x - std::floor(uv.x);
  const auto byte = [](float value) { return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f)); };
  return {byte(u), byte(uv.y), 96, 255};
}

std::vector<std::uint8_t> UvCodedPng(std::uint32_t size) {
  std::vector<glm::u8vec4> pixels(std::size_t{size} * size);
  for (std::uint32_t y = 0; y < size; ++y) {
    for (std::uint32_t x = 0; x < size; ++x) {
      const float side = static_cast<float>(size);
      const glm::vec2 uv((static_cast<float>(x) + 0.5f) / side, 1.0f - (static_cast<float>(y) + 0.5f) / side);
      pixels[std::size_t{y} * size + x] = UvCodedColour(uv);
    }
  }
  return EncodePng(size, size, pixels);
}

std::filesystem::path WriteTexturedIctIdentity(const std::filesystem::path& folder, const std::string& identity) {
  std::filesystem::create_directories(folder);
  std::string obj = ReadWhole(IctDir() / (identity + ".obj"));
  const std::string ict_library = "mtllib ICTFaceModelMaterial.mtl";
  if (const std::size_t at = obj.find(ict_library); at != std::string::npos) {
    obj.replace(at, ict_library.size(), "mtllib textured.mtl");
  }
  const std::filesystem::path path = folder / (identity + ".obj");
  WriteWhole(path, obj);
  WriteWhole(folder / "textured.mtl", TexturedMaterials(ReadWhole(IctDir() / "ICTFaceModelMaterial.mtl")));
  const std::vector<std::uint8_t> png = UvCodedPng(256);
  WriteWhole(folder / "albedo.png", std::string(png.begin(), png.end()));
  return path;
}

}  // namespace facerig::test
