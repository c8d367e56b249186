// OpenCV's Haar cascade as the photo's second face detector (face_cascade.h).
#include "facerig/offline/photo/face_cascade.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

#include <glm/geometric.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>

#include "facerig/runtime/error.h"

namespace facerig {
namespace {

constexpr const char* kCascadeName = "haarcascade_frontalface_alt2.xml";

bool IsRegularFile(const std::filesystem::path& path) {
  std::error_code error;
  return !path.empty() && std::filesystem::is_regular_file(path, error);
}

}  // namespace

std::filesystem::path DefaultFaceCascadePath() {
#ifdef FACERIG_CONFIGURED_FACE_CASCADE
  if (IsRegularFile(FACERIG_CONFIGURED_FACE_CASCADE)) return FACERIG_CONFIGURED_FACE_CASCADE;
#endif
  const char* variable = std::getenv("XDG_DATA_DIRS");
  const std::string_view dirs = variable != nullptr && *variable != '\0' ? variable : "/usr/local/share:/usr/share";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::filesystem::path dir(dirs.substr(start, end - start));
    for (const char* sub : {"opencv4/haarcascades", "opencv/haarcascades"}) {
      if (!dir.empty() && IsRegularFile(dir / sub / kCascadeName)) return dir / sub / kCascadeName;
    }
    start = end + 1;
  }
  return {};
}

ImageFaceBox DlibBoxFromHaar(const ImageFaceBox& haar, const HaarToDlibBox& correction) {
  const float width = static_cast<float>(haar.width());
  const float cx = 0.5f * static_cast<float>(haar.left + haar.right) + correction.dx * width;
  const float cy = 0.5f * static_cast<float>(haar.top + haar.bottom) + correction.dy * width;
  const float half = 0.5f * correction.scale * width;
  ImageFaceBox box;
  box.left = static_cast<int>(std::lround(cx - half));
  box.top = static_cast<int>(std::lround(cy - half));
  box.right = static_cast<int>(std::lround(cx + half));
  box.bottom = static_cast<int>(std::lround(cy + half));
  box.score = haar.score;
  return box;
}

ImageFaceBox DlibBoxFromPoints(std::span<const glm::vec2> points, const PointsToDlibBox& correction) {
  glm::vec2 mean(0.0f);
  for (const glm::vec2 p : points) mean += p;
  mean /= static_cast<float>(std::max<std::size_t>(1, points.size()));
  float squared = 0.0f;
  for (const glm::vec2 p : points) squared += glm::dot(p - mean, p - mean);
  const float spread = std::sqrt(squared / static_cast<float>(std::max<std::size_t>(1, points.size())));
  const glm::vec2 centre = mean + glm::vec2(correction.dx, correction.dy) * spread;
  const float half = 0.5f * correction.scale * spread;
  return {static_cast<int>(std::lround(centre.x - half)), static_cast<int>(std::lround(centre.y - half)),
          static_cast<int>(std::lround(centre.x + half)), static_cast<int>(std::lround(centre.y + half)), 0.0};
}

struct FaceCascade::Impl {
  cv::CascadeClassifier classifier;
};

FaceCascade::FaceCascade(const std::filesystem::path& file) : impl_(std::make_unique<Impl>()) {
  if (!IsRegularFile(file) || !std::ifstream(file)) {
    throw IoError(IoErrorKind::kOpenFailed, file.string(),
                  "cannot read OpenCV's Haar face cascade (Debian: apt install opencv-data)");
  }
  bool loaded = false;
  try {
    loaded = impl_->classifier.load(file.string());
  } catch (const cv::Exception& e) {
    throw IoError(IoErrorKind::kParse, file.string(), std::string("not a Haar cascade: ") + e.what());
  }
  if (!loaded || impl_->classifier.empty()) {
    throw IoError(IoErrorKind::kParse, file.string(), "not a Haar cascade OpenCV can load");
  }
}

FaceCascade::~FaceCascade() = default;
FaceCascade::FaceCascade(FaceCascade&&) noexcept = default;
FaceCascade& FaceCascade::operator=(FaceCascade&&) noexcept = default;

std::vector<ImageFaceBox> FaceCascade::DetectFaceBoxes(const RgbImage& image, int min_face_pixels) {
  const std::vector<std::uint8_t> grey = ToGray(image);
  // OpenCV does not write to the pixels: the cv::Mat only views them.
  const cv::Mat view(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(grey.data()));
  cv::Mat equalised;
  cv::equalizeHist(view, equalised);  // a face lit from one side: its dark half brought up
  std::vector<cv::Rect> rects;
  std::vector<int> neighbours;
  const int smallest = std::max(24, min_face_pixels);
  impl_->classifier.detectMultiScale(equalised, rects, neighbours, 1.1, 3, 0, cv::Size(smallest, smallest));
  std::vector<ImageFaceBox> boxes;
  for (std::size_t k = 0; k < rects.size(); ++k) {
    const cv::Rect& r = rects[k];
    boxes.push_back({r.x, r.y, r.x + r.width, r.y + r.height, k < neighbours.size() ? neighbours[k] : 0.0});
  }
  std::stable_sort(boxes.begin(), boxes.end(),
                   [](const ImageFaceBox& a, const ImageFaceBox& b) { return a.score > b.score; });
  return boxes;
}

}  // namespace facerig
