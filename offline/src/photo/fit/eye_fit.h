// The lid margins of a face deformed onto a photo's landmarks, put on the
// photo's lids (photo_rig.cpp).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/photo/fit.h"
#include "facerig/runtime/mesh.h"

namespace facerig {

struct LidMarginFit {
  int eyes = 0;             // eye openings found and fitted
  std::size_t margins = 0;  // margin vertices put on a lid
};

// A smooth deformation of the face on six dlib points an eye only leaves the
// lid margins between them where the head had them: the photo's lids then
// show above or below the head's openings. Here every vertex of each eye
// opening's rim (the skin's boundary loop nearest the eye's landmarks) goes
// onto the photo's lid, the upper rim on the polyline 36-37-38-39 (42-...-45),
// the lower on 39-40-41-36, at its place between the opening's corners
// (which go to 36 and 39); depth unchanged. The correction spreads over the
// lids smoothly (RbfDeformToLandmarks, the other landmark vertices held) and
// fades out within an eye width of the opening; each eyeball (with the
// layers over it) moves by its rim's mean offset, keeping the iris centred. `posed` (the face as the photo shows it, under `camera`) and
// `rest` take the same offsets. An eye the photo shows nearly closed (lids
// less than 0.12 eye widths apart) is left as it is.
// \pre surface's triangles index posed, posed.size() == rest.size(),
//      landmarks.size() == landmark_vertices.size() == 68.
LidMarginFit FitLidMarginsToPhoto(const Mesh& surface, std::span<const glm::vec2> landmarks,
                                  std::span<const std::uint32_t> landmark_vertices, const ScaledOrthoCamera& camera,
                                  int width, int height, std::vector<glm::vec3>& posed, std::vector<glm::vec3>& rest);

}  // namespace facerig
