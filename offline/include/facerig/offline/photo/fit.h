// A face model fitted to one photograph: dlib's 68 landmarks on the photo,
// then a linear face model (the template's neutral plus identity modes plus a
// few of its expressions) and a scaled orthographic camera fitted to them
// (the photo's points first corrected for a perspective camera's distance when
// one fits them better), alternating camera and shape (the method of Aldrian & Smith as the eos
// library uses it: closed-form camera, regularised linear least squares for
// the shape, jaw-line landmarks matched to the model's moving contour).
//
// The model (face_model.h), the camera (camera.h) and the landmarks
// (landmarks.h) have their own headers; the fallback for a template without
// identity modes (RbfDeformToLandmarks) is here.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/photo/camera.h"
#include "facerig/offline/photo/face_model.h"
#include "facerig/offline/photo/image.h"

namespace facerig {

struct PhotoShadingParams {
  int iterations = 4;
  // The shading term's weight: each sampled vertex counts this fraction of
  // one independent observation at the estimated pixel noise (neighbouring
  // samples of a blurred photo are not independent).
  double weight = 0.03;
  int max_samples = 3000;
  // The photo's blur (Gaussian sigma) in mean edge lengths of the face
  // region's triangles: more biases the shading at the nose and the masks' edges.
  float blur_edges = 0.05f;
  // Refine the camera too (else the landmark fit's stays).
  bool camera = true;
  // Vertices whose normal is nearer the image plane than this are left out.
  float min_facing = 0.3f;
};

struct PhotoFitParams {
  int iterations = 5;
  // Landmark noise as a fraction of the face size (the box of the 68 points):
  // with the N(0, 1) prior on identity weights this sets the regularisation.
  // 0.015: about the best of 0.01..0.08 on renders of random ICT identities.
  double landmark_sigma_fraction = 0.015;
  // Prior on the expression weights (N(0, expression_sigma^2), clamped to [0, 1]).
  double expression_sigma = 0.5;
  // The jaw line is less precise than the inner points (dlib, silhouettes).
  float jaw_weight = 0.5f;
  // dlib's brows (17..26) and eyes (36..47) scatter two to four times as far
  // as its nose and mouth points on renders of random faces.
  float brow_weight = 0.5f;
  float eye_weight = 0.3f;
  // The nose's points (27..35); 0 holds them out, to see how well a fit predicts them.
  float nose_weight = 1.0f;
  // With identity modes and the model's detector: rounds of dlib's offsets
  // measured on a render of the fit itself (from the photo's camera) in place
  // of the neutral's, each followed by a re-fit.
  int self_calibration_rounds = 1;
  // Jaw landmarks 0..16 except the chin's (7..9) follow the model's contour.
  bool moving_contour = true;
  // Move the detected points by the model's landmark_offsets.
  bool remove_landmark_offsets = true;
  // A model without identity modes (the built-in head) is then deformed
  // smoothly onto the landmarks (RbfDeformToLandmarks): the posed face onto
  // the photo's points, the rest face with the mouth and eyes as open as the
  // fitted expressions make them (an open mouth in the photo stays an
  // expression, not part of the face's shape).
  bool deform_without_identity = true;
  // A contour candidate is on the silhouette when |normal . view| is below this.
  float silhouette_cosine = 0.35f;
  // Camera distances from the face (model units: cm for ICT) tried with a
  // perspective camera besides the orthographic one, from a selfie's to a far
  // portrait's; the fit keeps the one whose objective (landmark residuals over
  // their variances plus the prior) is lowest. Empty: orthographic only.
  std::vector<float> camera_distances{25.0f, 35.0f, 50.0f, 70.0f, 100.0f, 150.0f, 250.0f};
  // Refine the landmark fit by the photo's shading (RefinePhotoFitByShading,
  // run by the FitPhoto that takes the photo). On renders it halves the
  // error; on real photos it predicts dlib's held-out nose points better.
  bool shading = true;
  PhotoShadingParams shading_params;
};

struct PhotoFit {
  ScaledOrthoCamera camera;
  RasterView view;  // the camera as a RasterView of the photo (perspective when camera_distance > 0)
  // The perspective camera's distance from the landmarks' centroid (model
  // units); 0: orthographic. `camera` then sees OrthographicPixels of the photo's points.
  float camera_distance = 0.0f;
  std::vector<float> identity_weights;
  std::vector<std::string> expression_names;
  std::vector<float> expression_weights;
  std::vector<glm::vec3> rest_positions;  // neutral + identity: the fitted face at rest
  std::vector<glm::vec3> posed_positions;  // rest + the fitted expressions: as in the photo
  std::vector<std::uint32_t> landmark_vertices;  // the 68 vertices used last (jaw on the contour)
  std::vector<glm::vec2> model_pixels;  // those vertices projected into the photo
  std::vector<glm::vec2> target_pixels;  // the points they were fitted to: dlib's moved by its offsets
  double rms_pixels = 0.0;  // landmark residual
  bool deformed = false;  // the RBF fallback moved the face (no identity modes)
  double seconds = 0.0;
  // The photo's light as the shading refinement fitted it at the final face
  // and camera: 9 second-order spherical-harmonic coefficients (the basis of
  // EvaluatePhotoLighting) per colour channel, sRGB in [0, 1], a constant skin
  // albedo absorbed, of camera-space normals (camera.rotation * world normal).
  // Empty when no shading fit ran.
  std::vector<glm::vec3> lighting;
};

// The fitted lighting's colour at a camera-space unit normal (zero when
// `lighting` does not hold 9 coefficients).
glm::vec3 EvaluatePhotoLighting(std::span<const glm::vec3> lighting, glm::vec3 camera_normal);

// \throw InvalidInputError when landmarks.size() != 68, a pixel is not finite,
//        or the image size is not positive.
PhotoFit FitPhoto(const PhotoFaceModel& model, std::span<const glm::vec2> landmarks, int width, int height,
                  const PhotoFitParams& params = {});

// --- the shading refinement (photo_shading_fit.cpp) ---

// Analysis by synthesis after the landmark fit: the camera and the identity
// and expression weights refined by Gauss-Newton on the landmark term and
// prior (FitPhoto's, jaw vertices fixed) plus the photo's shading at visible
// face-skin vertices (inside the 68 points' face outline, away from the eyes,
// brows, mouth and nostrils): the lightly blurred photo's colour at each
// vertex against second-order spherical-harmonic lighting of its normal (a
// constant albedo; the 9 x 3 lighting re-solved each step), residuals
// Huber-weighted, their weight from the robust pixel noise. `detected`:
// dlib's 68 points on `photo` (the masks). Without identity modes, a fit the
// RBF deformed, or too few skin vertices in view, `fit` is returned as is.
// \throw InvalidInputError when the photo's pixels do not match its size or
//        detected.size() != 68.
PhotoFit RefinePhotoFitByShading(const PhotoFaceModel& model, const RgbImage& photo,
                                 std::span<const glm::vec2> detected, const PhotoFit& fit,
                                 const PhotoFitParams& params = {});

// FitPhoto on the photo's landmarks, then, when params.shading,
// RefinePhotoFitByShading: the whole fit `facerig photo` runs.
// \throw InvalidInputError as those two.
PhotoFit FitPhoto(const PhotoFaceModel& model, const RgbImage& photo, std::span<const glm::vec2> landmarks,
                  const PhotoFitParams& params = {});

// The fallback without identity modes (rbf_fit.cpp).

// Moves `positions` so that each landmark vertex projects onto its pixel:
// the image-plane offsets at the landmark vertices (depth unchanged, from the
// head itself) interpolated over every vertex by a biharmonic radial basis
// function (phi(r) = r) with an affine part, the smoothest such deformation.
// \pre vertices.size() == pixels.size() >= 4, each vertex in range.
// \throw InvalidInputError on mismatched sizes or an index out of range.
void RbfDeformToLandmarks(std::span<glm::vec3> positions, std::span<const std::uint32_t> vertices,
                          std::span<const glm::vec2> pixels, const ScaledOrthoCamera& camera, int width, int height);

}  // namespace facerig
