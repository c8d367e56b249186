// The player's blend on the built-in head over a spoken line: only what
// moves is written, yet the buffers hold what a fresh blend state writes
// everywhere (nothing is left behind); positions are the whole-mesh blend's
// bit for bit, normals
// (blended from each shape's change of the recomputed ones) within a degree of
// the recomputed ones where the surface is smooth, the frames the same pixels
// as with recomputed normals within a stated tolerance, and no allocation.
#include "face_animator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "egl_context.h"
#include "face_renderer.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/blend_plan.h"
#include "facerig/runtime/io/rig_file.h"
#include "measure/allocation_counter.h"
#include "media_writer.h"

namespace {

double Degrees(const glm::vec3& a, const glm::vec3& b) {
  if (a == b) return 0.0;
  const double cosine = std::clamp(static_cast<double>(glm::dot(a, b)), -1.0, 1.0);
  return std::acos(cosine) * 180.0 / 3.14159265358979323846;
}

// Per vertex, the largest angle between its (recomputed) normal and the
// normals of its triangles: small where the surface is smooth, large on
// creases (lip line, mouth corners, eyelid rims) and at sharp corners.
std::vector<double> CreaseDegrees(const facerig::Rig& rig, const std::vector<glm::vec3>& positions,
                                  const std::vector<glm::vec3>& normals) {
  std::vector<double> crease(rig.vertex_count(), 0.0);
  for (const facerig::Triangle& t : rig.triangles()) {
    const glm::vec3 n = glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
    if (glm::dot(n, n) == 0.0f) continue;
    const glm::vec3 face = glm::normalize(n);
    for (std::uint32_t v : t) crease[v] = std::max(crease[v], Degrees(face, normals[v]));
  }
  return crease;
}

double Percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(p * static_cast<double>(values.size() - 1))];
}

struct PixelDifference {
  int max = 0;
  double mean = 0.0;
};

PixelDifference Compare(const facerig::player::Image& a, const facerig::player::Image& b) {
  PixelDifference d;
  double sum = 0.0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) {
    if (i % 4 == 3) continue;  // alpha
    const int diff = std::abs(static_cast<int>(a.rgba[i]) - static_cast<int>(b.rgba[i]));
    d.max = std::max(d.max, diff);
    sum += diff;
  }
  d.mean = sum / static_cast<double>(a.rgba.size() / 4 * 3);
  return d;
}

}  // namespace

TEST_CASE("Player: the blend writes only what moves, normals near the recomputed ones, same pixels",
          "[demo]") {
  const facerig::Rig rig = facerig::LoadRig(FACERIG_DEFAULT_HEAD);
  facerig::player::FaceAnimator animator(rig);
  facerig::EspeakPhonemeSource source;
  const facerig::SpeechLine line = source.Synthesize("Bring me the map before the boat leaves the bay.", "en-us");
  REQUIRE(animator.character().Speak(line.phonemes, facerig::Seconds(0.2)) == facerig::CharacterError::kNone);
  animator.character().SetEmotion(facerig::Emotion::kJoy, 0.5f);

  facerig::player::HeadlessGlContext context;
  facerig::player::FaceRenderer renderer(rig);
  facerig::player::OffscreenTarget target(320, 240);
  std::vector<glm::vec3> positions(rig.vertex_count()), normals(rig.vertex_count());
  const facerig::BlendPlan plan = facerig::BlendPlan::Build(rig);  // for a fresh state each frame
  std::vector<glm::vec3> fresh_positions(rig.vertex_count()), fresh_normals(rig.vertex_count());
  std::vector<double> smooth_angles, all_angles, written;
  PixelDifference worst_pixels;
  double worst_mean = 0.0;
  std::size_t allocations = 0;
  const int frames = static_cast<int>((0.4 + line.audio_duration().count()) * 60.0);
  for (int frame = 0; frame < frames; ++frame) {
    {
      facerig::test::AllocationCounter counter;
      animator.Update(frame / 60.0);
      allocations += counter.count();
    }
    const facerig::BlendJob whole{&rig, animator.weights(), facerig::NormalMode::kRecompute, positions, normals};
    REQUIRE(whole.Run() == facerig::BlendJobError::kNone);
    INFO("frame " << frame);
    REQUIRE(std::memcmp(animator.positions().data(), positions.data(), positions.size() * sizeof(glm::vec3)) == 0);
    facerig::BlendState fresh(plan);
    const facerig::BlendJob from_scratch{&rig, animator.weights(), facerig::NormalMode::kBlendRecomputedDeltas,
                                         fresh_positions, fresh_normals, &fresh};
    REQUIRE(from_scratch.Run() == facerig::BlendJobError::kNone);
    REQUIRE(std::memcmp(animator.normals().data(), fresh_normals.data(), normals.size() * sizeof(glm::vec3)) == 0);
    written.push_back(static_cast<double>(animator.last_blend_work().moved_vertices) /
                      static_cast<double>(rig.vertex_count()));
    if (frame % 3 != 0) continue;  // the angles every third frame, the pixels every 30th
    const std::vector<double> crease = CreaseDegrees(rig, positions, normals);
    for (std::size_t v = 0; v < rig.vertex_count(); ++v) {
      const double angle = Degrees(animator.normals()[v], normals[v]);
      all_angles.push_back(angle);
      if (crease[v] <= 30.0) smooth_angles.push_back(angle);
    }
    if (frame % 30 != 0) continue;
    facerig::player::Image blended, recomputed;
    renderer.Upload(animator.positions(), animator.normals());
    target.Bind();
    renderer.Draw(target.width(), target.height(), animator.head_rotation());
    target.Read(&blended);
    renderer.Upload(positions, normals);
    target.Bind();
    renderer.Draw(target.width(), target.height(), animator.head_rotation());
    target.Read(&recomputed);
    const PixelDifference d = Compare(blended, recomputed);
    worst_pixels.max = std::max(worst_pixels.max, d.max);
    worst_mean = std::max(worst_mean, d.mean);
  }
  const double smooth_share = static_cast<double>(smooth_angles.size()) / static_cast<double>(all_angles.size());
  WARN(frames << " frames at 60 fps: positions written per frame, median " << 100.0 * Percentile(written, 0.5)
              << " % of the vertices; normals against the recomputed ones where smooth (" << 100.0 * smooth_share
              << " % of the vertices, no triangle over 30 degrees off the normal): max " << Percentile(smooth_angles, 1.0)
              << ", p99 " << Percentile(smooth_angles, 0.99) << " deg; everywhere: max " << Percentile(all_angles, 1.0)
              << ", p99 " << Percentile(all_angles, 0.99) << " deg; frames at 320x240 against recomputed normals: max "
              << worst_pixels.max << " / 255 in a channel, mean at most " << worst_mean);
  REQUIRE(allocations == 0);
  REQUIRE(Percentile(smooth_angles, 1.0) <= 1.0);
  REQUIRE(Percentile(all_angles, 0.99) <= 0.5);
  REQUIRE(smooth_share > 0.95);
  REQUIRE(worst_mean < 0.05);
  REQUIRE(worst_pixels.max <= 16);
  // Speech moves much of the head, but never all of it.
  REQUIRE(Percentile(written, 1.0) < 1.0);
  REQUIRE(Percentile(written, 1.0) > 0.0);
}
