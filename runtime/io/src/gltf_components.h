// Decoding of single accessor components (glTF's integer and float types),
// for the glTF reader. Private to facerig::runtime_io.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <tiny_gltf.h>

namespace facerig::gltf_internal {

inline std::uint32_t LoadU32(const unsigned char* p) {
  // GLB is little-endian, as is every platform facerig builds on.
  std::uint32_t value;
  std::memcpy(&value, p, sizeof(value));
  return value;
}

inline std::size_t ComponentSize(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

inline const char* TypeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    default:
      return "a matrix";
  }
}

inline int ComponentsOf(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;
  }
}

// Float attributes may also be (normalized) integers (KHR_mesh_quantization).
inline float LoadAsFloat(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float value;
      std::memcpy(&value, p, sizeof(value));
      return value;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto value = static_cast<float>(static_cast<std::int8_t>(*p));
      return normalized ? std::max(value / 127.0f, -1.0f) : value;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const auto value = static_cast<float>(*p);
      return normalized ? value / 255.0f : value;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t raw;
      std::memcpy(&raw, p, sizeof(raw));
      const auto value = static_cast<float>(raw);
      return normalized ? std::max(value / 32767.0f, -1.0f) : value;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t raw;
      std::memcpy(&raw, p, sizeof(raw));
      const auto value = static_cast<float>(raw);
      return normalized ? value / 65535.0f : value;
    }
    default:
      return 0.0f;
  }
}

inline std::uint32_t LoadIndex(const unsigned char* p, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t value;
      std::memcpy(&value, p, sizeof(value));
      return value;
    }
    default:
      return LoadU32(p);
  }
}

inline bool IsIndexType(int component_type) {
  return component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

}  // namespace facerig::gltf_internal
