// Landmark files (JSON) and the debug drawing of a detection.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"

namespace facerig {

RgbImage DrawLandmarks(const LandmarkResult& result) {
  RgbImage image = result.image;
  auto put = [&](int x, int y, std::array<std::uint8_t, 3> colour) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                               static_cast<std::size_t>(x));
    for (std::size_t c = 0; c < 3; ++c) image.pixels[i + c] = colour[c];
  };
  for (std::size_t k = 0; k < result.pixels.size(); ++k) {
    const bool jaw = k < 17;
    const bool snapped = k < result.landmarks.confidence.size() &&
                         result.landmarks.confidence[k] < (jaw ? 0.999f * 0.3f : 0.999f);
    const std::array<std::uint8_t, 3> colour = snapped ? std::array<std::uint8_t, 3>{255, 60, 60}
                                               : jaw   ? std::array<std::uint8_t, 3>{255, 210, 0}
                                                       : std::array<std::uint8_t, 3>{40, 255, 80};
    const int cx = static_cast<int>(std::floor(result.pixels[k].x));
    const int cy = static_cast<int>(std::floor(result.pixels[k].y));
    for (int d = -2; d <= 2; ++d) {
      put(cx + d, cy, colour);
      put(cx, cy + d, colour);
    }
  }
  return image;
}

void WriteLandmarksJson(const std::filesystem::path& path, const FaceLandmarks& landmarks) {
  if (landmarks.confidence.size() != landmarks.points.size() ||
      (!landmarks.indices.empty() && landmarks.indices.size() != landmarks.points.size())) {
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "landmark points, confidences and indices differ in length");
  }
  nlohmann::json json;
  json["format"] = "facerig-landmarks";
  json["version"] = 1;
  json["order"] = "dlib-68";
  nlohmann::json points = nlohmann::json::array();
  for (const glm::vec3& p : landmarks.points) points.push_back({p.x, p.y, p.z});
  json["points"] = std::move(points);
  json["confidence"] = landmarks.confidence;
  if (!landmarks.indices.empty()) json["indices"] = landmarks.indices;
  const std::filesystem::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << json.dump(1) << "\n";
    if (!out) throw IoError(IoErrorKind::kWriteFailed, temporary.string(), "cannot write the landmark file");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "cannot rename the landmark file into place");
  }
}

namespace {

[[noreturn]] void FailLandmarks(IoErrorKind kind, const std::string& name, const std::string& problem) {
  throw IoError(kind, name, problem);
}

std::vector<glm::vec3> LandmarkPoints(const nlohmann::json& json, const std::string& name) {
  if (!json.is_object() || !json.contains("points") || !json["points"].is_array()) {
    FailLandmarks(IoErrorKind::kParse, name, "expected an object with a \"points\" array");
  }
  std::vector<glm::vec3> points;
  for (const auto& p : json["points"]) {
    if (!p.is_array() || p.size() != 3) {
      FailLandmarks(IoErrorKind::kParse, name,
                    "points[" + std::to_string(points.size()) + "]: each point must be [x, y, z]");
    }
    const glm::vec3 point(p[0].get<float>(), p[1].get<float>(), p[2].get<float>());
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z)) {
      FailLandmarks(IoErrorKind::kNonFinite, name,
                    "points[" + std::to_string(points.size()) + "]: a landmark point is not finite");
    }
    points.push_back(point);
  }
  if (points.empty()) FailLandmarks(IoErrorKind::kEmpty, name, "the landmark file has no points");
  return points;
}

void ReadConfidenceAndIndices(const nlohmann::json& json, const std::string& name, FaceLandmarks& landmarks) {
  const std::size_t n = landmarks.points.size();
  if (json.contains("confidence")) {
    landmarks.confidence = json["confidence"].get<std::vector<float>>();
    for (float c : landmarks.confidence) {
      if (!(c >= 0.0f && c <= 1.0f)) FailLandmarks(IoErrorKind::kParse, name, "confidence: must be in [0, 1]");
    }
  } else {
    landmarks.confidence.assign(n, 1.0f);
  }
  if (json.contains("indices")) {
    // Each an integer: nlohmann casts a float such as 3.6e55 to uint32 unchecked (found by fuzzing).
    const nlohmann::json& indices = json["indices"];
    if (!indices.is_array() ||
        !std::all_of(indices.begin(), indices.end(), [](const nlohmann::json& i) { return i.is_number_unsigned(); })) {
      FailLandmarks(IoErrorKind::kParse, name, "indices: expected an array of landmark indices 0..67");
    }
    for (const nlohmann::json& i : indices) {
      if (i.get<std::uint64_t>() > 67) {
        FailLandmarks(IoErrorKind::kParse, name,
                      "indices: landmark index " + std::to_string(i.get<std::uint64_t>()) + " is outside dlib's 0..67");
      }
      landmarks.indices.push_back(static_cast<std::uint32_t>(i.get<std::uint64_t>()));
    }
  } else {
    for (std::uint32_t i = 0; i < n; ++i) landmarks.indices.push_back(i);
  }
  if (landmarks.confidence.size() != n || landmarks.indices.size() != n) {
    FailLandmarks(IoErrorKind::kParse, name, "\"points\", \"confidence\" and \"indices\" must have the same length");
  }
  for (std::uint32_t i : landmarks.indices) {
    if (i >= kDlibLandmarkCount) {
      FailLandmarks(IoErrorKind::kIndexOutOfRange, name,
                    "indices: landmark index " + std::to_string(i) + " is outside dlib's 0..67");
    }
  }
}

}  // namespace

FaceLandmarks ParseLandmarksJson(std::string_view text, const std::string& name) {
  if (text.size() > kMaxLandmarkFileBytes) {
    FailLandmarks(IoErrorKind::kAbsurdCount, name,
                  std::to_string(text.size()) + " bytes (at most " + std::to_string(kMaxLandmarkFileBytes) + ")");
  }
  CheckJsonNesting(text, name);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    FailLandmarks(IoErrorKind::kParse, name, "not JSON: " + QuoteInput(e.what()));
  }
  FaceLandmarks landmarks;
  try {
    landmarks.points = LandmarkPoints(json, name);
    ReadConfidenceAndIndices(json, name, landmarks);
  } catch (const nlohmann::json::exception& e) {
    FailLandmarks(IoErrorKind::kParse, name, "malformed landmark file: " + QuoteInput(e.what()));
  }
  return landmarks;
}

FaceLandmarks ReadLandmarksJson(const std::filesystem::path& path) {
  return ParseLandmarksJson(ReadInputText(path, kMaxLandmarkFileBytes), path.string());
}

}  // namespace facerig
