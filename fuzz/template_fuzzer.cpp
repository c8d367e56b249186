// Template descriptor JSON (face_template.h), checked against a small grid rig
// of 100 vertices with the parts "skin" and "teeth".
#include <cstdint>
#include <string>

#include "facerig/offline/error.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/rig_builder.h"
#include "fuzz_input.h"

namespace {

facerig::Rig GridRig() {
  constexpr std::uint32_t kSide = 10;
  facerig::RawRig raw;
  for (std::uint32_t y = 0; y < kSide; ++y) {
    for (std::uint32_t x = 0; x < kSide; ++x) raw.positions.emplace_back(float(x), float(y), 0.0f);
  }
  for (std::uint32_t y = 0; y + 1 < kSide; ++y) {
    for (std::uint32_t x = 0; x + 1 < kSide; ++x) {
      const std::uint32_t v = y * kSide + x;
      raw.triangles.push_back({v, v + 1, v + kSide});
      raw.triangles.push_back({v + 1, v + kSide + 1, v + kSide});
    }
  }
  const auto half = static_cast<std::uint32_t>(raw.triangles.size() / 2);
  raw.parts = {{"skin", 0, half}, {"teeth", half, static_cast<std::uint32_t>(raw.triangles.size()) - half}};
  return *facerig::RigBuilder::Build(std::move(raw));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const facerig::Rig rig = GridRig();
  try {
    facerig::ParseFaceTemplateInfo(std::string(facerig::fuzz::Text(data, size)), rig, "input.template.json");
  } catch (const facerig::IoError&) {
  } catch (const facerig::InvalidInputError&) {
  }
  return 0;
}
