// A textured face through `facerig convert` and `facerig build`: the image
// reaches every output byte for byte, and every corner keeps the UV it had,
// so each corner shows the same texel as in the artist's file. The written
// files are also read without facerig's readers: their images decoded
// (OpenCV) and their UVs taken from the GLB accessors and OBJ lines, so that
// a flipped or swapped image or UV shows as wrong colours on the face.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "cli/app.h"
#include "facerig/offline/io/image_codec.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/part_roles.h"
#include "support/command_runner.h"
#include "support/gltf_validator.h"
#include "support/skinned_gltf.h"
#include "support/test_meshes.h"
#include "support/textured_assets.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> FileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The rig's face material shows the albedo, byte for byte, and its corners
// carry the source's UVs (triangle t of the rig is triangle t of the source
// grouped by part, as builds and LoadRig order them).
void CheckTextured(const Rig& rig, const Mesh& source, const std::vector<std::uint8_t>& albedo) {
  const auto face = std::find_if(rig.materials().begin(), rig.materials().end(),
                                 [](const Material& m) { return m.name == "M_Face"; });
  REQUIRE(face != rig.materials().end());
  REQUIRE(face->base_colour_image >= 0);
  CHECK(rig.images()[static_cast<std::size_t>(face->base_colour_image)].bytes == albedo);
  REQUIRE(rig.triangle_count() == source.triangle_count());
  REQUIRE(!rig.uvs().empty());
  std::size_t mismatches = 0;
  for (std::size_t t = 0; t < source.triangle_count(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      const glm::vec2 uv = rig.uvs()[rig.triangles()[t][c]];
      if (glm::length(uv - source.corner_uvs[t * 3 + c]) > 1e-6f) ++mismatches;
    }
  }
  CHECK(mismatches == 0);
}

// --- pixels: the written images decoded and sampled ---

// RGBA, 8 bits a channel; the test fails on bytes that do not decode.
cv::Mat DecodeRgba(std::span<const std::uint8_t> bytes) {
  const cv::Mat decoded = DecodeImageBytes(bytes, DecodedChannels::kBgra);
  cv::Mat rgba;
  cv::cvtColor(decoded, rgba, cv::COLOR_BGRA2RGBA);
  return rgba;
}

glm::u8vec4 Texel(const cv::Mat& rgba, int x, int y) {
  const cv::Vec4b p = rgba.at<cv::Vec4b>(y, x);
  return {p[0], p[1], p[2], p[3]};
}

// Which way v runs: up from the bottom row (OBJ, facerig's rigs) or down from
// the top row (glTF).
enum class VAxis { kUp, kDown };

// The texel that `uv` falls in, repeating outside [0, 1] as glTF's default sampler does.
glm::u8vec4 Sample(const cv::Mat& rgba, glm::vec2 uv, VAxis axis) {
  const float down = axis == VAxis::kUp ? 1.0f - uv.y : uv.y;
  const auto index = [](float t, int size) {
    const auto i = static_cast<int>(std::floor((t - std::floor(t)) * static_cast<float>(size)));
    return std::clamp(i, 0, size - 1);
  };
  return Texel(rgba, index(uv.x, rgba.cols), index(down, rgba.rows));
}

bool Near(glm::u8vec4 a, glm::u8vec4 b, int tolerance) {
  for (int i = 0; i < 4; ++i) {
    if (std::abs(int{a[i]} - int{b[i]}) > tolerance) return false;
  }
  return true;
}

// The image is the UV-coded albedo the right way up: texels at its corners,
// middle and off the diagonals show the colour of the UV at their centre,
// row 0 at the top (v = 1).
void CheckUvCodedTexels(const cv::Mat& rgba) {
  REQUIRE(rgba.cols == 256);
  REQUIRE(rgba.rows == 256);
  constexpr std::pair<int, int> kTexels[] = {{0, 0}, {255, 0}, {0, 255}, {255, 255}, {128, 128}, {40, 200}, {230, 17}};
  for (const auto& [x, y] : kTexels) {
    const glm::vec2 centre((static_cast<float>(x) + 0.5f) / 256.0f, 1.0f - (static_cast<float>(y) + 0.5f) / 256.0f);
    CAPTURE(x, y);
    CHECK(Texel(rgba, x, y) == test::UvCodedColour(centre));
  }
}

// Corner k of the written face shows the colour that corner k of the
// source's face shows in the source albedo (a texel apart at most: an OBJ
// writes UVs in decimal).
void CheckFaceColours(const cv::Mat& written_image, std::span<const glm::vec2> written_uvs, VAxis written_axis,
                      const cv::Mat& source_image, std::span<const glm::vec2> source_uvs) {
  REQUIRE(written_uvs.size() == source_uvs.size());
  REQUIRE(!written_uvs.empty());
  std::size_t mismatches = 0;
  std::string first;
  for (std::size_t k = 0; k < source_uvs.size(); ++k) {
    const glm::u8vec4 expected = Sample(source_image, source_uvs[k], VAxis::kUp);
    const glm::u8vec4 shown = Sample(written_image, written_uvs[k], written_axis);
    if (!Near(shown, expected, 2) && mismatches++ == 0) {
      const auto rgb = [](glm::u8vec4 c) {
        return std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b);
      };
      first = "corner " + std::to_string(k) + " shows " + rgb(shown) + ", the source " + rgb(expected);
    }
  }
  INFO(first);
  CHECK(mismatches == 0);
}

// The UVs of the face part's corners, in triangle order.
std::vector<glm::vec2> FaceCornerUvs(const Mesh& source) {
  REQUIRE(source.triangle_parts.size() == source.triangle_count());
  std::vector<glm::vec2> uvs;
  for (std::size_t t = 0; t < source.triangle_count(); ++t) {
    if (source.part_names[source.triangle_parts[t]] != "M_Face") continue;
    uvs.insert(uvs.end(), source.corner_uvs.begin() + static_cast<long>(3 * t),
               source.corner_uvs.begin() + static_cast<long>(3 * t + 3));
  }
  return uvs;
}

std::vector<glm::vec2> FaceCornerUvs(const Rig& rig) {
  const Part* face = rig.FindPart("M_Face");
  REQUIRE(face);
  std::vector<glm::vec2> uvs;
  for (std::uint32_t t = face->first_triangle; t < face->first_triangle + face->triangle_count; ++t) {
    for (const std::uint32_t v : rig.triangles()[t]) uvs.push_back(rig.uvs()[v]);
  }
  return uvs;
}

// --- a .glb read as JSON and buffers: the face primitive ---

// The face material's image, decoded.
cv::Mat FaceImage(const Rig& rig) {
  const Part* face = rig.FindPart("M_Face");
  REQUIRE(face);
  REQUIRE(face->material >= 0);
  const std::int32_t image = rig.materials()[static_cast<std::size_t>(face->material)].base_colour_image;
  REQUIRE(image >= 0);
  return DecodeRgba(rig.images()[static_cast<std::size_t>(image)].bytes);
}

// The elements of a glTF accessor as T (float VEC2, an unsigned index type).
template <typename T>
std::vector<T> AccessorValues(const test::GltfFile& file, int accessor) {
  const std::vector<unsigned char> bytes = test::AccessorBytes(file, accessor);
  REQUIRE(bytes.size() % sizeof(T) == 0);
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

std::vector<std::uint32_t> ReadIndices(const test::GltfFile& file, int accessor) {
  switch (file.document["accessors"][accessor]["componentType"].get<int>()) {
    case 5121: { const auto v = AccessorValues<std::uint8_t>(file, accessor); return {v.begin(), v.end()}; }
    case 5123: { const auto v = AccessorValues<std::uint16_t>(file, accessor); return {v.begin(), v.end()}; }
    default: return AccessorValues<std::uint32_t>(file, accessor);
  }
}

// The face material's image, decoded, and the TEXCOORD_0 of its primitive's
// corners in triangle order, as stored (v down).
struct GlbFace {
  cv::Mat image;
  std::vector<glm::vec2> corner_uvs;
};

GlbFace ReadGlbFace(const fs::path& path) {
  const test::GltfFile file = test::ReadGltfFile(path);
  const nlohmann::json& document = file.document;
  GlbFace face;
  for (const nlohmann::json& mesh : document["meshes"]) {
    for (const nlohmann::json& primitive : mesh["primitives"]) {
      if (!primitive.contains("material")) continue;
      const nlohmann::json& material = document["materials"][primitive["material"].get<int>()];
      if (material["name"] != "M_Face") continue;
      const int texture = material["pbrMetallicRoughness"]["baseColorTexture"]["index"];
      const std::vector<unsigned char> image = test::ImageBytes(file, document["textures"][texture]["source"]);
      face.image = DecodeRgba(image);
      const int uv_accessor = primitive["attributes"]["TEXCOORD_0"];
      REQUIRE(document["accessors"][uv_accessor]["type"] == "VEC2");
      const std::vector<glm::vec2> uvs = AccessorValues<glm::vec2>(file, uv_accessor);
      for (const std::uint32_t v : ReadIndices(file, primitive["indices"])) face.corner_uvs.push_back(uvs.at(v));
    }
  }
  REQUIRE(!face.image.empty());
  return face;
}

// --- an OBJ folder read as text: the face's vt per corner and its map_Kd ---

struct ObjFace {
  cv::Mat image;
  std::vector<glm::vec2> corner_uvs;  // v up
};

ObjFace ReadObjFace(const fs::path& obj_path) {
  std::ifstream obj(obj_path);
  std::vector<glm::vec2> vts;
  std::string line, library, material;
  ObjFace face;
  while (std::getline(obj, line)) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "mtllib") words >> library;
    if (word == "usemtl") words >> material;
    if (word == "vt") {
      glm::vec2 uv;
      words >> uv.x >> uv.y;
      vts.push_back(uv);
    }
    if (word != "f" || material != "M_Face") continue;
    std::string corner;
    int corners = 0;
    for (; words >> corner; ++corners) {
      const std::size_t slash = corner.find('/');
      REQUIRE(slash != std::string::npos);
      face.corner_uvs.push_back(vts.at(std::stoul(corner.substr(slash + 1)) - 1));
    }
    REQUIRE(corners == 3);
  }
  std::ifstream mtl(obj_path.parent_path() / library);
  std::string texture;
  for (bool in_face = false; std::getline(mtl, line);) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "newmtl") in_face = line.substr(7) == "M_Face";
    if (in_face && word == "map_Kd") texture = line.substr(line.rfind(' ') + 1);
  }
  REQUIRE(!texture.empty());
  face.image = DecodeRgba(FileBytes(obj_path.parent_path() / texture));
  return face;
}

}  // namespace

TEST_CASE("(shared data) facerig convert and build keep a textured ICT face's image, UVs and materials",
          "[shared-data][cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_textures");
  const fs::path obj = test::WriteTexturedIctIdentity(folder / "in");
  const std::vector<std::uint8_t> albedo = FileBytes(folder / "in" / "albedo.png");
  const Mesh source = GroupedByPart(ReadObj(obj));
  REQUIRE(source.images.size() == 1);
  const cv::Mat source_image = DecodeRgba(albedo);
  CheckUvCodedTexels(source_image);
  const std::vector<glm::vec2> source_face = FaceCornerUvs(source);
  // Each output's image decoded is the albedo the right way up, and its UVs
  // put the source's colour on each corner of the face.
  const auto check_pixels = [&](const cv::Mat& image, std::span<const glm::vec2> uvs, VAxis axis) {
    CheckUvCodedTexels(image);
    CheckFaceColours(image, uvs, axis, source_image, source_face);
  };

  const test::CommandOutcome converted =
      test::RunCommand(cli::RunFacerig, {"convert", obj.string(), (folder / "converted.glb").string()});
  INFO(converted.error_output);
  REQUIRE(converted.exit_code == 0);
  test::RequireValidatorAccepts(folder / "converted.glb");
  CheckTextured(LoadRig(folder / "converted.glb"), source, albedo);
  {
    INFO("converted.glb");
    const GlbFace face = ReadGlbFace(folder / "converted.glb");
    check_pixels(face.image, face.corner_uvs, VAxis::kDown);
  }

  const test::CommandOutcome built = test::RunCommand(
      cli::RunFacerig, {"build", "--template", test::IctDir().string(), "--target", obj.string(), "-o",
                        (folder / "built.glb").string(), "--frig", (folder / "built.frig").string(), "--obj-dir",
                        (folder / "objs").string()});
  INFO(built.error_output);
  REQUIRE(built.exit_code == 0);
  test::RequireValidatorAccepts(folder / "built.glb");
  CheckTextured(LoadRig(folder / "built.glb"), source, albedo);
  CheckTextured(LoadRig(folder / "built.frig"), source, albedo);
  {
    INFO("built.glb");
    const GlbFace face = ReadGlbFace(folder / "built.glb");
    check_pixels(face.image, face.corner_uvs, VAxis::kDown);
  }
  {
    INFO("built.frig");
    const Rig frig = LoadRig(folder / "built.frig");
    check_pixels(FaceImage(frig), FaceCornerUvs(frig), VAxis::kUp);
  }
  {
    INFO("objs/neutral.obj");
    const ObjFace face = ReadObjFace(folder / "objs" / "neutral.obj");
    check_pixels(face.image, face.corner_uvs, VAxis::kUp);
  }
  // ICT's MTL gives its eye layers and lashes an opaque grey: the build gives
  // them their role's blended material, so they never cover the eyes.
  const Rig built_rig = LoadRig(folder / "built.glb");
  for (const Part& part : built_rig.parts()) {
    REQUIRE(part.material >= 0);
    const Material& material = built_rig.materials()[static_cast<std::size_t>(part.material)];
    INFO(part.name << ": " << material.name);
    CHECK(material.name == part.name);
    const bool layer = part.name == "M_EyeOcclusion" || part.name == "M_LacrimalFluid" || part.name == "M_EyeBlend" ||
                       part.name == "M_EyeLashes";
    CHECK((material.alpha_mode == AlphaMode::kBlend) == layer);
    if (part.name != "M_Face") CHECK(!IsPlaceholderMaterial(material));
  }
  // The OBJ folder shares one MTL and the image under its own name.
  CHECK(fs::exists(folder / "objs" / "materials.mtl"));
  const Mesh neutral = ReadObj(folder / "objs" / "neutral.obj");
  // The face's albedo, and the eyes and lashes painted by the build (eye_textures.h).
  REQUIRE(neutral.images.size() == 6);
  CHECK(std::count_if(neutral.images.begin(), neutral.images.end(),
                      [&](const EncodedImage& image) { return image.bytes == albedo; }) == 1);
  // Shapes under their ARKit names (the default --names arkit), the baked visemes among them.
  const Mesh blink = ReadObj(folder / "objs" / "eyeBlinkLeft.obj");
  REQUIRE(blink.images.size() == 6);
  CHECK(blink.corner_uvs == neutral.corner_uvs);
  const Mesh viseme = ReadObj(folder / "objs" / "viseme_PP.obj");
  CHECK(viseme.positions.size() == neutral.positions.size());
}

}  // namespace facerig
