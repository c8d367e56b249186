// dlib reads the default head as a human face. (The only translation unit
// that includes dlib: it is slow to compile.)
#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>

#include <cstdio>
#include <filesystem>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/render/rasterizer.h"
#include "support/default_head_poses.h"

namespace {

constexpr int kImageSize = 400;

dlib::point Centre(const dlib::full_object_detection& shape, unsigned first, unsigned last) {
  long x = 0, y = 0;
  for (unsigned i = first; i <= last; ++i) {
    x += shape.part(i).x();
    y += shape.part(i).y();
  }
  const long n = static_cast<long>(last - first + 1);
  return {x / n, y / n};
}

float Distance(const dlib::point& a, const glm::vec3& b) {
  return glm::length(glm::vec2(static_cast<float>(a.x()), static_cast<float>(a.y())) - glm::vec2(b));
}

}  // namespace

TEST_CASE("Default head: dlib finds the face and its landmarks where the head has them",
          "[default_head][dlib]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  // Front-on, orthographic, the whole head in view (as a portrait photo).
  const facerig::RasterView view =
      facerig::RasterView::Orbit({0.0f, -1.5f, 0.0f}, 14.0f, kImageSize, kImageSize);
  const facerig::RgbImage image = facerig::RenderRig(rig, rig.positions(), rig.normals(), view);
  facerig::WritePng(std::filesystem::path(FACERIG_TEST_OUTPUT_DIR) / "default_head_dlib_input.png", image);
  const std::vector<std::uint8_t> gray = facerig::ToGray(image);
  dlib::array2d<unsigned char> dlib_image(kImageSize, kImageSize);
  for (int y = 0; y < kImageSize; ++y) {
    for (int x = 0; x < kImageSize; ++x) dlib_image[y][x] = gray[static_cast<std::size_t>(y * kImageSize + x)];
  }

  dlib::frontal_face_detector detector = dlib::get_frontal_face_detector();
  const std::vector<dlib::rectangle> faces = detector(dlib_image);
  REQUIRE(faces.size() == 1);

  dlib::shape_predictor predictor;
  dlib::deserialize(FACERIG_DLIB_SHAPE_PREDICTOR) >> predictor;
  const dlib::full_object_detection shape = predictor(dlib_image, faces[0]);
  REQUIRE(shape.num_parts() == 68);

  // The head's own points, projected. dlib's 36-41 is the eye on the image's
  // left, i.e. the character's right (-X); 42-47 the character's left.
  const glm::vec3 radius_forward{0.0f, 0.0f, features.eyeball_radius};
  const glm::vec3 eye_left = facerig::ProjectToImage(view, features.eye_centres[0] + radius_forward);
  const glm::vec3 eye_right = facerig::ProjectToImage(view, features.eye_centres[1] + radius_forward);
  const glm::vec3 nose = facerig::ProjectToImage(view, rig.positions()[features.nose_tip]);
  const glm::vec3 mouth = 0.5f * (facerig::ProjectToImage(view, rig.positions()[features.mouth_corners[0]]) +
                                  facerig::ProjectToImage(view, rig.positions()[features.mouth_corners[1]]));
  const float error_right_eye = Distance(Centre(shape, 36, 41), eye_right);
  const float error_left_eye = Distance(Centre(shape, 42, 47), eye_left);
  const float error_nose = Distance(shape.part(30), nose);
  const float error_mouth = Distance(Centre(shape, 48, 67), mouth);
  const float interocular = glm::length(glm::vec2(eye_left) - glm::vec2(eye_right));
  std::printf("dlib on the default head (%d px, interocular %.1f px): face %ldx%ld px; landmark errors "
              "right eye %.1f, left eye %.1f, nose tip %.1f, mouth centre %.1f px\n",
              kImageSize, static_cast<double>(interocular), faces[0].width(), faces[0].height(),
              static_cast<double>(error_right_eye), static_cast<double>(error_left_eye),
              static_cast<double>(error_nose), static_cast<double>(error_mouth));
  // dlib's model errs by a few percent of the interocular distance on real
  // photos; on an untextured stylized render allow 4% of the image width
  // (16 px, about a fifth of the interocular distance): enough to tell the
  // eyes from the brows and the nose tip from the mouth, which sit farther apart.
  const float tolerance = 0.04f * kImageSize;
  CHECK(error_right_eye < tolerance);
  CHECK(error_left_eye < tolerance);
  CHECK(error_nose < tolerance);
  CHECK(error_mouth < tolerance);
}
