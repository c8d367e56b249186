#include "gl_textures.h"

#include <algorithm>
#include <string>

#include <epoxy/gl.h>
#include <opencv2/imgproc.hpp>

#include "facerig/offline/io/image_codec.h"

namespace facerig::player {
namespace {

// Any depth and channel count imdecode gives -> 8-bit RGBA.
cv::Mat ToRgba8(const cv::Mat& decoded) {
  cv::Mat eight_bit = decoded;
  if (decoded.depth() == CV_16U) decoded.convertTo(eight_bit, CV_8U, 1.0 / 257.0);
  cv::Mat rgba;
  switch (eight_bit.channels()) {
    case 1: cv::cvtColor(eight_bit, rgba, cv::COLOR_GRAY2RGBA); break;
    case 3: cv::cvtColor(eight_bit, rgba, cv::COLOR_BGR2RGBA); break;
    case 4: cv::cvtColor(eight_bit, rgba, cv::COLOR_BGRA2RGBA); break;
    default: break;  // two channels (grey + alpha) are rare; empty: the caller reports it
  }
  return rgba;
}

enum class Role { kBaseColour, kNormal };

// 8x anisotropic filtering where the GPU has it; none on a software
// rasteriser (Mesa llvmpipe, the headless path's usual renderer), where it
// doubles the draw time of a textured face.
float AnisotropyToUse() {
  if (!epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic") &&
      !epoxy_has_gl_extension("GL_ARB_texture_filter_anisotropic")) {
    return 1.0f;
  }
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string name = renderer != nullptr ? renderer : "";
  for (const char* software : {"llvmpipe", "softpipe", "SwiftShader"}) {
    if (name.find(software) != std::string::npos) return 1.0f;
  }
  GLfloat max_anisotropy = 1.0f;
  glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT, &max_anisotropy);
  return std::min(max_anisotropy, 8.0f);
}

GLuint Upload(const cv::Mat& rgba, Role role, float anisotropy) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // Base colours are sRGB-encoded: the sampler returns linear values and
  // mipmaps average in linear light. Normal maps are data.
  const GLint format = role == Role::kBaseColour ? GL_SRGB8_ALPHA8 : GL_RGBA8;
  // Row 0 (the image's top) goes to t = 0; the shader samples at t = 1 - v
  // because the rig's UVs have their origin at the image's bottom-left.
  glTexImage2D(GL_TEXTURE_2D, 0, format, rgba.cols, rgba.rows, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data);
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  if (anisotropy > 1.0f) glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY_EXT, anisotropy);
  glBindTexture(GL_TEXTURE_2D, 0);
  return texture;
}

}  // namespace

bool DecodeRgba(const EncodedImage& image, cv::Mat* rgba, std::string* problem) {
  const auto fail = [&](const std::string& why) {
    if (problem) *problem = "image \"" + image.name + "\": " + why;
    return false;
  };
  if (image.bytes.empty()) return fail("no bytes");
  cv::Mat decoded;
  try {
    decoded = DecodeImageBytes(image.bytes, DecodedChannels::kBgra);
  } catch (const std::exception& e) {
    return fail(std::string("cannot decode (") + e.what() + ")");
  }
  if (decoded.empty()) return fail(std::string("cannot decode its ") + (image.format == ImageFormat::kPng ? "PNG" : "JPEG") + " bytes");
  if (static_cast<std::uint32_t>(decoded.cols) != image.width ||
      static_cast<std::uint32_t>(decoded.rows) != image.height) {
    return fail("decodes to " + std::to_string(decoded.cols) + "x" + std::to_string(decoded.rows) +
                ", its header says " + std::to_string(image.width) + "x" + std::to_string(image.height));
  }
  *rgba = ToRgba8(decoded);
  if (rgba->empty()) return fail("unsupported channel count " + std::to_string(decoded.channels()));
  return true;
}

RigTextures::RigTextures(const Rig& rig)
    : base_colour_(rig.images().size(), 0), normal_(rig.images().size(), 0) {
  const std::span<const EncodedImage> images = rig.images();
  std::vector<bool> as_base(images.size(), false), as_normal(images.size(), false);
  const auto mark = [&](std::vector<bool>& used, std::int32_t index) {
    if (index >= 0 && static_cast<std::size_t>(index) < used.size()) used[static_cast<std::size_t>(index)] = true;
  };
  for (const facerig::Material& material : rig.materials()) {
    mark(as_base, material.base_colour_image);
    mark(as_normal, material.normal_image);
  }
  const float anisotropy = AnisotropyToUse();
  for (std::size_t i = 0; i < images.size(); ++i) {
    if (!as_base[i] && !as_normal[i]) continue;
    cv::Mat rgba;
    std::string problem;
    if (!DecodeRgba(images[i], &rgba, &problem)) {
      problems_.push_back(problem + "; its parts draw with their colour alone");
      continue;
    }
    if (as_base[i]) base_colour_[i] = Upload(rgba, Role::kBaseColour, anisotropy);
    if (as_normal[i]) normal_[i] = Upload(rgba, Role::kNormal, anisotropy);
  }
}

RigTextures::~RigTextures() {
  for (const std::vector<unsigned>* textures : {&base_colour_, &normal_}) {
    for (unsigned texture : *textures) {
      if (texture != 0) glDeleteTextures(1, &texture);
    }
  }
}

unsigned RigTextures::Find(const std::vector<unsigned>& textures, std::int32_t index) {
  if (index < 0 || static_cast<std::size_t>(index) >= textures.size()) return 0;
  return textures[static_cast<std::size_t>(index)];
}

}  // namespace facerig::player
