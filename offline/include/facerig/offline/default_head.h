// The project's own built-in default head (data/default_head.glb, .frig).
//
// Built with the method of paper 002 (section II, Table I): a low-poly
// control face of named feature points (MPEG-4 FDP-like), refined by 2 linear
// + 2 Loop subdivisions into a dense mesh with per-vertex correspondence
// (dense = S * control, S sparse) and projected onto a sculpted surface.
// Expressions authored on the control mesh become dense blend shapes through
// the same S; the jaw, lids and eyeballs rotate about their pivots. Eyeballs
// (white, iris, pupil), teeth, tongue and the inner mouth are separate parts.
//
// Units: centimetres, +Y up, the face looks along +Z, the character's left is
// +X; shape names and _L/_R as ICT-FaceKit (ARKit names).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

namespace facerig {

// Points and vertex chains of the default head, for tests and landmarking.
// Index [0] is the character's left (+X), [1] the right.
struct DefaultHeadFeatures {
  std::array<glm::vec3, 2> eye_centres{};
  float eyeball_radius = 0.0f;
  std::uint32_t nose_tip = 0;                     // skin vertex
  std::array<std::uint32_t, 2> mouth_corners{};   // skin vertices
  // Lid and lip margins (skin vertices on the openings), from one corner to
  // the other, corners excluded; upper[i] meets lower[i] when closed.
  std::array<std::vector<std::uint32_t>, 2> upper_lid, lower_lid;
  std::vector<std::uint32_t> upper_lip, lower_lip;
  std::uint32_t skin_vertex_count = 0;            // skin vertices come first
  std::uint32_t control_vertex_count = 0;
  std::uint32_t control_triangle_count = 0;
};

// Deterministic: the same rig, bit for bit, on every run.
Rig BuildDefaultHead(DefaultHeadFeatures* features = nullptr);

// Writes small PNG previews of the head (front and three-quarter views of
// neutral, jawOpen, smile, blink, and a mid-speech pose) into `directory`.
// Returns the files written.
std::vector<std::filesystem::path> WriteDefaultHeadPreviews(const Rig& rig,
                                                            const std::filesystem::path& directory,
                                                            int size = 256);

}  // namespace facerig
