#include "support/skinned_gltf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <string_view>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "facerig/runtime/files/atomic_file.h"
#include "support/base64.h"

namespace facerig::test {
namespace {

using nlohmann::json;

constexpr std::array<unsigned char, 76> kPng = {
    0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A, 0x00, 0x00, 0x00, 0x0D, 0x49, 0x48, 0x44, 0x52, 0x00,
    0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x02, 0x00, 0x00, 0x00, 0xFD, 0xD4, 0x9A, 0x73, 0x00,
    0x00, 0x00, 0x13, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9C, 0x63, 0xF8, 0xCF, 0xC0, 0xC0, 0x00, 0xC2, 0x0C,
    0xFF, 0x81, 0x80, 0x01, 0x00, 0x25, 0xE9, 0x05, 0xFB, 0xA8, 0x7D, 0xF2, 0x2D, 0x00, 0x00, 0x00, 0x00,
    0x49, 0x45, 0x4E, 0x44, 0xAE, 0x42, 0x60, 0x82};

// Accessors and views appended to one buffer, as an exporter lays them out.
class Builder {
 public:
  template <typename T>
  int Accessor(std::span<const T> values, int component_type, const char* type, std::size_t count,
               int target = 0, bool normalized = false) {
    while (data_.size() % 4 != 0) data_.push_back(0);
    json view = {{"buffer", 0}, {"byteOffset", data_.size()}, {"byteLength", values.size_bytes()}};
    if (target != 0) view["target"] = target;
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    data_.insert(data_.end(), bytes, bytes + values.size_bytes());
    views_.push_back(view);
    json accessor = {{"bufferView", views_.size() - 1}, {"componentType", component_type}, {"count", count},
                     {"type", type}};
    if (normalized) accessor["normalized"] = true;
    accessors_.push_back(accessor);
    return static_cast<int>(accessors_.size()) - 1;
  }
  int View(std::span<const unsigned char> bytes) {
    while (data_.size() % 4 != 0) data_.push_back(0);
    views_.push_back({{"buffer", 0}, {"byteOffset", data_.size()}, {"byteLength", bytes.size()}});
    data_.insert(data_.end(), bytes.begin(), bytes.end());
    return static_cast<int>(views_.size()) - 1;
  }
  json& LastAccessor() { return accessors_.back(); }

  std::vector<unsigned char> data_;
  json views_ = json::array();
  json accessors_ = json::array();
};

glm::mat4 Transform(const json& node) {
  glm::mat4 m(1.0f);
  if (node.contains("translation")) {
    m = glm::translate(m, glm::vec3(node["translation"][0].get<float>(), node["translation"][1].get<float>(),
                                    node["translation"][2].get<float>()));
  }
  if (node.contains("rotation")) {
    const json& r = node["rotation"];
    m *= glm::mat4_cast(glm::quat(r[3].get<float>(), r[0].get<float>(), r[1].get<float>(), r[2].get<float>()));
  }
  if (node.contains("scale")) {
    m = glm::scale(m, glm::vec3(node["scale"][0].get<float>(), node["scale"][1].get<float>(),
                                node["scale"][2].get<float>()));
  }
  return m;
}

}  // namespace

void WriteSkinnedGltf(const std::filesystem::path& path, const std::vector<SkinnedPrimitive>& primitives,
                      const SkinnedGltfOptions& options) {
  const bool binary = path.extension() == ".glb";
  Builder b;
  constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedInt = 5125;
  constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

  // Joints: root -> neck -> head, each moved and turned; the mesh node is a
  // sibling of the root, as exporters write skinned meshes.
  json nodes = json::array({
      {{"name", "root"}, {"translation", {0.0, 0.1, 0.0}}, {"children", {1}}},
      {{"name", "neck"}, {"translation", {0.0, 0.5, 0.02}}, {"rotation", {0.0871557, 0.0, 0.0, 0.9961947}},
       {"children", {2}}},
      {{"name", "head"}, {"translation", {0.0, 0.2, 0.05}}, {"rotation", {0.0, 0.1736482, 0.0, 0.9848078}},
       {"scale", {1.0, 1.0, 1.0}}},
      {{"name", "face"}, {"mesh", 0}, {"skin", 0}},
  });
  std::vector<float> inverse_binds;
  {
    const glm::mat4 root = Transform(nodes[0]);
    const glm::mat4 neck = root * Transform(nodes[1]);
    const glm::mat4 head = neck * Transform(nodes[2]);
    for (const glm::mat4& bind : {root, neck, head}) {
      const glm::mat4 inverse = glm::inverse(bind);
      inverse_binds.insert(inverse_binds.end(), glm::value_ptr(inverse), glm::value_ptr(inverse) + 16);
    }
  }

  json gltf_primitives = json::array();
  for (const SkinnedPrimitive& primitive : primitives) {
    const std::size_t n = primitive.positions.size();
    float lo = primitive.positions.front().y, hi = lo;
    for (const glm::vec3& p : primitive.positions) {
      lo = std::min(lo, p.y);
      hi = std::max(hi, p.y);
    }
    std::vector<std::array<std::uint8_t, 4>> joints(n), colors(n);
    std::vector<std::array<float, 4>> weights(n);
    std::vector<glm::vec2> uv1(n);
    for (std::size_t v = 0; v < n; ++v) {
      const float t = hi > lo ? (primitive.positions[v].y - lo) / (hi - lo) : 0.5f;
      // A joint with no weight is 0, as the validator asks.
      joints[v] = {static_cast<std::uint8_t>(t < 1.0f ? 1 : 0), static_cast<std::uint8_t>(t > 0.0f ? 2 : 0), 0, 0};
      weights[v] = {1.0f - t, t, 0.0f, 0.0f};
      colors[v] = {static_cast<std::uint8_t>(v * 7 % 256), static_cast<std::uint8_t>(v * 13 % 256), 200, 255};
      uv1[v] = {primitive.positions[v].x, t};
    }
    json attributes;
    attributes["POSITION"] = b.Accessor(std::span<const glm::vec3>(primitive.positions), kFloat, "VEC3", n, kArrayBuffer);
    glm::vec3 min = primitive.positions.front(), max = min;
    for (const glm::vec3& p : primitive.positions) {
      min = glm::min(min, p);
      max = glm::max(max, p);
    }
    b.LastAccessor()["min"] = {min.x, min.y, min.z};
    b.LastAccessor()["max"] = {max.x, max.y, max.z};
    if (!primitive.normals.empty()) {
      attributes["NORMAL"] = b.Accessor(std::span<const glm::vec3>(primitive.normals), kFloat, "VEC3", n, kArrayBuffer);
    }
    // The material's texture needs TEXCOORD_0: made up when not given.
    attributes["TEXCOORD_0"] = b.Accessor(std::span<const glm::vec2>(primitive.uvs.empty() ? uv1 : primitive.uvs),
                                          kFloat, "VEC2", n, kArrayBuffer);
    attributes["TEXCOORD_1"] = b.Accessor(std::span<const glm::vec2>(uv1), kFloat, "VEC2", n, kArrayBuffer);
    attributes["COLOR_0"] = b.Accessor(std::span<const std::array<std::uint8_t, 4>>(colors), kUnsignedByte, "VEC4", n,
                                       kArrayBuffer, true);
    attributes["JOINTS_0"] =
        b.Accessor(std::span<const std::array<std::uint8_t, 4>>(joints), kUnsignedByte, "VEC4", n, kArrayBuffer);
    attributes["WEIGHTS_0"] = b.Accessor(std::span<const std::array<float, 4>>(weights), kFloat, "VEC4", n, kArrayBuffer);
    const int indices = b.Accessor(std::span<const Triangle>(primitive.triangles), kUnsignedInt, "SCALAR",
                                   primitive.triangles.size() * 3, kElementArrayBuffer);
    gltf_primitives.push_back({{"attributes", attributes}, {"indices", indices}, {"material", 0}});
  }
  if (options.with_lines) {
    // The first triangle's edges, as lines on the first primitive's vertices.
    const Triangle& t = primitives.front().triangles.front();
    const std::array<std::uint32_t, 6> lines = {t[0], t[1], t[1], t[2], t[2], t[0]};
    const int indices = b.Accessor(std::span<const std::uint32_t>(lines), kUnsignedInt, "SCALAR", 6, kElementArrayBuffer);
    json attributes = gltf_primitives.front()["attributes"];
    gltf_primitives.push_back({{"attributes", attributes}, {"indices", indices}, {"mode", 1}, {"material", 0}});
  }

  const int inverse_bind_matrices = b.Accessor(std::span<const float>(inverse_binds), kFloat, "MAT4", 3);
  const std::array<float, 3> times = {0.0f, 0.5f, 1.0f};
  const int input = b.Accessor(std::span<const float>(times), kFloat, "SCALAR", 3);
  b.LastAccessor()["min"] = {0.0};
  b.LastAccessor()["max"] = {1.0};
  const std::array<float, 12> rotations = {0, 0, 0, 1, 0.2588190f, 0, 0, 0.9659258f, 0, 0, 0, 1};
  const int output = b.Accessor(std::span<const float>(rotations), kFloat, "VEC4", 3);

  json image = {{"name", "skin colour"}};
  if (binary) {
    image["bufferView"] = b.View(kPng);
    image["mimeType"] = "image/png";
  } else {
    image["uri"] = "data:image/png;base64," + Base64Encode(kPng);
  }

  json buffer = {{"byteLength", b.data_.size()}};
  if (!binary) buffer["uri"] = "data:application/octet-stream;base64," + Base64Encode(b.data_);
  json document = {
      {"asset", {{"version", "2.0"}, {"generator", "facerig test exporter"}}},
      {"extensionsUsed", {"KHR_materials_emissive_strength"}},
      {"scene", 0},
      {"scenes", {{{"name", "character"}, {"nodes", {0, 3}}}}},
      {"nodes", nodes},
      {"skins", {{{"name", "rig"}, {"joints", {0, 1, 2}}, {"skeleton", 0}, {"inverseBindMatrices", inverse_bind_matrices}}}},
      {"meshes", {{{"name", "face"}, {"primitives", gltf_primitives}, {"extras", {{"artist", "kept"}}}}}},
      {"materials",
       {{{"name", "skin"},
         {"pbrMetallicRoughness",
          {{"baseColorTexture", {{"index", 0}, {"texCoord", 0}}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.6}}},
         {"emissiveFactor", {0.1, 0.0, 0.0}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2.0}}}}}}}},
      {"textures", {{{"sampler", 0}, {"source", 0}}}},
      {"samplers", {{{"magFilter", 9729}, {"minFilter", 9729}, {"wrapS", 33071}, {"wrapT", 33071}}}},
      {"images", {image}},
      {"animations",
       {{{"name", "nod"},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "rotation"}}}}}},
         {"samplers", {{{"input", input}, {"output", output}, {"interpolation", "LINEAR"}}}}}}},
      {"bufferViews", b.views_},
      {"accessors", b.accessors_},
      {"buffers", {buffer}},
  };

  const std::string text = document.dump();
  if (!binary) {
    WriteFileAtomically(path, text);
    return;
  }
  std::string padded = text;
  while (padded.size() % 4 != 0) padded += ' ';
  std::vector<unsigned char> bin = b.data_;
  while (bin.size() % 4 != 0) bin.push_back(0);
  std::vector<std::byte> glb;
  auto put32 = [&glb](std::uint32_t value) {
    for (int i = 0; i < 4; ++i) glb.push_back(static_cast<std::byte>((value >> (8 * i)) & 0xFF));
  };
  put32(0x46546C67);  // "glTF"
  put32(2);
  put32(static_cast<std::uint32_t>(12 + 8 + padded.size() + 8 + bin.size()));
  put32(static_cast<std::uint32_t>(padded.size()));
  put32(0x4E4F534A);
  for (char c : padded) glb.push_back(static_cast<std::byte>(c));
  put32(static_cast<std::uint32_t>(bin.size()));
  put32(0x004E4942);
  for (unsigned char c : bin) glb.push_back(static_cast<std::byte>(c));
  WriteFileAtomically(path, glb);
}

GltfFile ReadGltfFile(const std::filesystem::path& path) {
  const std::vector<std::byte> bytes = ReadFileBytes(path);
  GltfFile file;
  std::vector<unsigned char> bin;
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, bytes.data() + 12, 4);
    const auto* text = reinterpret_cast<const char*>(bytes.data() + 20);
    file.document = json::parse(text, text + json_length);
    const std::size_t bin_header = 20 + json_length;
    if (bin_header + 8 <= bytes.size()) {
      std::uint32_t bin_length = 0;
      std::memcpy(&bin_length, bytes.data() + bin_header, 4);
      const auto* data = reinterpret_cast<const unsigned char*>(bytes.data() + bin_header + 8);
      bin.assign(data, data + bin_length);
    }
  } else {
    const auto* text = reinterpret_cast<const char*>(bytes.data());
    file.document = json::parse(text, text + bytes.size());
  }
  for (const json& buffer : file.document["buffers"]) {
    const std::string uri = buffer.value("uri", "");
    const std::size_t comma = uri.find(',');
    file.buffers.push_back(uri.empty() ? bin : Base64Decode(std::string_view(uri).substr(comma + 1)));
  }
  return file;
}

std::vector<unsigned char> AccessorBytes(const GltfFile& file, int accessor) {
  static const std::map<std::string, std::size_t> kComponents = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3},
                                                                 {"VEC4", 4}, {"MAT4", 16}};
  const json& a = file.document["accessors"][accessor];
  const int component_type = a["componentType"].get<int>();
  const std::size_t component_size = component_type == 5120 || component_type == 5121   ? 1
                                     : component_type == 5122 || component_type == 5123 ? 2
                                                                                         : 4;
  const std::size_t element_size = component_size * kComponents.at(a["type"].get<std::string>());
  const json& view = file.document["bufferViews"][a["bufferView"].get<int>()];
  const std::vector<unsigned char>& buffer = file.buffers.at(view["buffer"].get<std::size_t>());
  const std::size_t stride = view.value("byteStride", element_size);
  const std::size_t start = view.value("byteOffset", std::size_t{0}) + a.value("byteOffset", std::size_t{0});
  std::vector<unsigned char> out;
  for (std::size_t i = 0; i < a["count"].get<std::size_t>(); ++i) {
    const auto first = buffer.begin() + static_cast<std::ptrdiff_t>(start + i * stride);
    out.insert(out.end(), first, first + static_cast<std::ptrdiff_t>(element_size));
  }
  return out;
}

std::vector<unsigned char> ImageBytes(const GltfFile& file, int image) {
  const json& view = file.document["bufferViews"][file.document["images"][image]["bufferView"].get<int>()];
  const std::vector<unsigned char>& buffer = file.buffers.at(view["buffer"].get<std::size_t>());
  const auto first = buffer.begin() + view.value("byteOffset", std::ptrdiff_t{0});
  return {first, first + view["byteLength"].get<std::ptrdiff_t>()};
}

std::span<const unsigned char> TexturePng() { return kPng; }

}  // namespace facerig::test
