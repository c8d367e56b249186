// The default head's materials: painted skin, a painted eye (sclera, iris,
// pupil on the eyeball's disc UVs), painted teeth (default_head_teeth.cpp), a
// pink tongue and a mouth interior that darkens from the lips inwards; and the eye texture, painted in code like the skin.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <opencv2/imgproc.hpp>

#include "default_head/albedo.h"
#include "default_head/angles.h"

namespace facerig::default_head {
namespace {

// Linear RGB from 8-bit sRGB, as glTF's base colour factor wants it.
glm::vec4 Linear(int r, int g, int b) {
  auto channel = [](int c) {
    const double s = c / 255.0;
    return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
  };
  return {channel(r), channel(g), channel(b), 1.0f};
}

Material MakeMaterial(const char* name, glm::vec4 colour, std::int32_t image, float roughness) {
  Material m;
  m.name = name;
  m.base_colour = colour;
  m.base_colour_image = image;
  m.roughness = roughness;
  return m;
}

// Sclera: white, pinker and greyer towards the back, with a few veins.
void PaintSclera(cv::Mat& eye, double iris_radius) {
  const int size = eye.rows;
  const cv::Point2f centre(0.5f * static_cast<float>(size), 0.5f * static_cast<float>(size));
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double r = cv::norm(cv::Point2f(static_cast<float>(x), static_cast<float>(y)) - centre);
      const float back = static_cast<float>(std::clamp((r - 1.6 * iris_radius) / (2.0 * iris_radius), 0.0, 1.0));
      eye.at<cv::Vec3f>(y, x) = Bgr(0.94f, 0.92f, 0.89f) * (1.0f - back) + Bgr(0.88f, 0.74f, 0.72f) * back;
    }
  }
  cv::Mat veins(size, size, CV_8U, cv::Scalar::all(0));
  cv::RNG rng(51);
  for (int v = 0; v < 28; ++v) {
    double angle = rng.uniform(0.0, 2.0 * kPi), r = 3.2 * iris_radius;
    cv::Point2f p = centre + cv::Point2f(static_cast<float>(r * std::cos(angle)), static_cast<float>(r * std::sin(angle)));
    for (int step = 0; step < 8; ++step) {
      angle += rng.uniform(-0.12, 0.12);
      r -= rng.uniform(0.1, 0.25) * iris_radius;
      const cv::Point2f q = centre + cv::Point2f(static_cast<float>(r * std::cos(angle)), static_cast<float>(r * std::sin(angle)));
      cv::line(veins, p, q, cv::Scalar(rng.uniform(120, 255)), 1, cv::LINE_AA);
      p = q;
      if (r < 1.25 * iris_radius) break;
    }
  }
  cv::Mat soft;
  veins.convertTo(soft, CV_32F, 0.2 / 255.0);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const float a = soft.at<float>(y, x);
      eye.at<cv::Vec3f>(y, x) = eye.at<cv::Vec3f>(y, x) * (1.0f - a) + Bgr(0.72f, 0.30f, 0.30f) * a;
    }
  }
}

// Iris: radial fibres in two tones, a warm collarette round the pupil, a
// dark limbal ring at its edge; the pupil black.
void PaintIris(cv::Mat& eye, double iris_radius, double pupil_radius) {
  const int size = eye.rows;
  const cv::Point2f centre(0.5f * static_cast<float>(size), 0.5f * static_cast<float>(size));
  cv::Mat fibres(size, size, CV_8U, cv::Scalar::all(90));
  cv::RNG rng(52);
  for (int i = 0; i < 900; ++i) {
    const double angle = rng.uniform(0.0, 2.0 * kPi), wobble = rng.uniform(-0.08, 0.08);
    const cv::Point2f dir(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
    const cv::Point2f bent(static_cast<float>(std::cos(angle + wobble)), static_cast<float>(std::sin(angle + wobble)));
    cv::line(fibres, centre + dir * static_cast<float>(pupil_radius), centre + bent * static_cast<float>(iris_radius),
             cv::Scalar(rng.uniform(30, 255)), 1, cv::LINE_AA);
  }
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double r = cv::norm(cv::Point2f(static_cast<float>(x), static_cast<float>(y)) - centre);
      const double edge = std::clamp(iris_radius + 1.5 - r, 0.0, 1.0);  // anti-aliased iris edge
      if (edge <= 0.0) continue;
      const float f = fibres.at<std::uint8_t>(y, x) / 255.0f;
      cv::Vec3f iris = Bgr(0.22f, 0.33f, 0.42f) * (1.0f - f) + Bgr(0.45f, 0.58f, 0.66f) * f;
      const float collarette = static_cast<float>(std::exp(-std::pow((r - 1.7 * pupil_radius) / (0.35 * pupil_radius), 2.0)));
      iris = iris * (1.0f - 0.6f * collarette) + Bgr(0.55f, 0.42f, 0.24f) * (0.6f * collarette);
      const float limbus = static_cast<float>(std::clamp((r - 0.82 * iris_radius) / (0.18 * iris_radius), 0.0, 1.0));
      iris = iris * (1.0f - 0.75f * limbus) + Bgr(0.08f, 0.10f, 0.12f) * (0.75f * limbus);
      const float pupil = static_cast<float>(std::clamp(pupil_radius + 0.5 - r, 0.0, 1.0));
      iris = iris * (1.0f - pupil) + Bgr(0.02f, 0.02f, 0.02f) * pupil;
      cv::Vec3f& c = eye.at<cv::Vec3f>(y, x);
      c = c * static_cast<float>(1.0 - edge) + iris * static_cast<float>(edge);
    }
  }
}

}  // namespace

EncodedImage PaintMouthAlbedo() {
  // Rows are depth into the mouth: the moist red of the inner lips, then the
  // shadowed cavity, so a crack between closed lips never shows black.
  const int size = kMouthTextureSize;
  cv::Mat mouth(size, size, CV_32FC3);
  const cv::Vec3f lips = Bgr(0.62f, 0.30f, 0.31f), cavity = Bgr(0.26f, 0.09f, 0.10f), back = Bgr(0.10f, 0.03f, 0.04f);
  for (int y = 0; y < size; ++y) {
    const float depth = (static_cast<float>(y) + 0.5f) / static_cast<float>(size);
    const float a = std::clamp(depth / 0.2f, 0.0f, 1.0f), b = std::clamp((depth - 0.2f) / 0.5f, 0.0f, 1.0f);
    const cv::Vec3f c = (lips * (1.0f - a) + cavity * a) * (1.0f - b) + back * b;
    for (int x = 0; x < size; ++x) mouth.at<cv::Vec3f>(y, x) = c;
  }
  return EncodeFloatBgrPng(mouth, "default_head_mouth.png");
}

EncodedImage PaintEyeAlbedo() {
  const int size = kEyeTextureSize;
  cv::Mat eye(size, size, CV_32FC3);
  const double r = Anatomy::kEyeRadius;
  const double iris = EyeUvRadius(std::asin(Anatomy::kIrisRadius / r)) * size;
  const double pupil = EyeUvRadius(std::asin(Anatomy::kPupilRadius / r)) * size;
  PaintSclera(eye, iris);
  PaintIris(eye, iris, pupil);
  return EncodeFloatBgrPng(eye, "default_head_eye.png");
}

void DressHead(RawRig& raw, const HeadGeometry& head) {
  raw.uvs = HeadUvs(head);
  raw.images = {PaintSkinAlbedo(head, raw.uvs), PaintEyeAlbedo(), PaintTeethAlbedo(), PaintMouthAlbedo()};
  // Painted with image rows going down; a rig's v goes up (OBJ's convention, rig.h).
  for (glm::vec2& uv : raw.uvs) uv.y = 1.0f - uv.y;
  raw.materials = {
      MakeMaterial("skin", glm::vec4(1.0f), 0, 0.6f),
      MakeMaterial("eye", glm::vec4(1.0f), 1, 0.1f),
      MakeMaterial("teeth", glm::vec4(1.0f), 2, 0.35f),
      MakeMaterial("tongue", Linear(150, 66, 72), -1, 0.5f),
      MakeMaterial("mouth_inner", glm::vec4(1.0f), 3, 0.75f),
  };
  for (RawPart& part : raw.parts) {
    const std::string& n = part.name;
    if (n == "skin") part.material = 0;
    else if (n.starts_with("eye_white") || n.starts_with("iris") || n.starts_with("pupil")) part.material = 1;
    else if (n.starts_with("teeth")) part.material = 2;
    else if (n == "tongue") part.material = 3;
    else if (n == "mouth_inner") part.material = 4;
  }
}

}  // namespace facerig::default_head
