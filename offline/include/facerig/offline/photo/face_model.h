// The linear face model a photo is fitted with: the template's neutral plus
// identity modes plus a few of its expressions, with the vertices that carry
// dlib's 68 landmarks. Identity modes are the template's identity meshes minus
// its neutral (ICT-FaceKit's identityNNN.obj): each is one mode at one standard
// deviation, so the prior on each weight is N(0, 1). Expressions are the
// template's own blend shapes, fitted with weights in [0, 1], so that a smiling
// or open-mouthed photo still yields a neutral rest face.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/runtime/rig.h"

namespace facerig {

struct PhotoModelParams {
  // Template blend shapes fitted along with the identity (those the rig lacks are skipped).
  std::vector<std::string> expressions{"jawOpen",       "mouthSmile_L", "mouthSmile_R", "mouthStretch_L",
                                       "mouthStretch_R", "mouthFunnel",  "mouthPucker",  "eyeBlink_L",
                                       "eyeBlink_R",     "browInnerUp",  "browDown_L",   "browDown_R"};
};

struct PhotoFaceModel {
  std::vector<glm::vec3> neutral;  // every vertex of the template
  std::vector<std::vector<glm::vec3>> identity_modes;  // identity mesh - neutral, every vertex
  std::vector<std::string> expression_names;
  std::vector<std::vector<glm::vec3>> expression_deltas;  // dense, every vertex
  std::vector<std::uint32_t> landmark_vertices;  // dlib's 68
  // Face-region vertices the jaw-line landmarks may move to (the lower face's sides and chin).
  std::vector<std::uint32_t> contour_candidates;
  std::vector<Triangle> region_triangles;  // triangles of the face region (contour normals)
  VertexRange region;
  // dlib's systematic offset from each landmark vertex (image x right, y down,
  // fractions of the 68 points' box size), measured on the template's own
  // neutral; zero when not calibrated. The fit moves each detected point by
  // it: the model's landmark vertices are not exactly where dlib puts them.
  std::vector<glm::vec2> landmark_offsets;
  // What a photo shows of the model (the transparent eye layers left out): the detector's renders.
  std::vector<Triangle> visible_triangles;
  std::vector<glm::vec3> visible_albedo;  // per visible triangle: skin, white eyes, dark lashes and mouth
  // The detector the offsets were measured with (not owned; null: none). With
  // it FitPhoto measures dlib's offsets again on a render of its own fit.
  LandmarkDetector* detector = nullptr;

  std::size_t unknown_count() const { return identity_modes.size() + expression_deltas.size(); }
};

// `identities`: whole meshes with the rig's vertex count (may be empty: the
// model then has expressions only). With a detector, landmark_offsets are
// measured on a render of the rig's neutral (LandmarkDetector::Detect).
// \throw InvalidInputError when the descriptor has no 68 landmark vertices or
//        an identity mesh has the wrong vertex count; LandmarkDetectionError
//        when the detector finds no face on the neutral.
PhotoFaceModel BuildPhotoFaceModel(const Rig& rig, const FaceTemplateInfo& info,
                                   std::span<const std::vector<glm::vec3>> identities,
                                   const PhotoModelParams& params = {}, LandmarkDetector* detector = nullptr);

// dlib's offsets (each landmark vertex's projection - dlib's point, in
// fractions of the 68 points' box; zero for the jaw but the chin) on a
// render of `positions` (the model's vertices) in the model's visible_albedo through `view`.
// \throw LandmarkDetectionError when dlib finds no face on the render.
std::vector<glm::vec2> MeasureDlibOffsets(const PhotoFaceModel& model, std::span<const glm::vec3> positions,
                                          RasterView view, LandmarkDetector& detector);

// identity000.obj, identity001.obj, ... from `folder` while they exist (at most
// max_count), read through ReadObj (input_file.h checks).
// \throw IoError on an unreadable file; InvalidInputError when one's vertex
//        count differs from `vertex_count`.
std::vector<std::vector<glm::vec3>> LoadIdentityMeshes(const std::filesystem::path& folder, std::size_t vertex_count,
                                                       std::size_t max_count = 100);

}  // namespace facerig
