// The player's blend on the built-in head over a spoken line: only what
// moves is written, and the positions and normals the renderer gets are the
// whole-mesh blend's, bit for bit, so the frames are the same pixels.
#include "face_animator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/io/rig_file.h"

namespace {

// Degrees between two unit normals (0 for the same bits).
double AngleDegrees(const glm::vec3& a, const glm::vec3& b) {
  if (a == b) return 0.0;
  const double cosine = std::clamp(static_cast<double>(glm::dot(a, b)), -1.0, 1.0);
  return std::acos(cosine) * 180.0 / 3.14159265358979323846;
}

}  // namespace

TEST_CASE("Player: the blend writes only what moves and equals the whole-mesh blend over a spoken line",
          "[demo]") {
  const facerig::Rig rig = facerig::LoadRig(FACERIG_DEFAULT_HEAD);
  facerig::player::FaceAnimator animator(rig);
  facerig::EspeakPhonemeSource source;
  const facerig::SpeechLine line = source.Synthesize("Bring me the map before the boat leaves the bay.", "en-us");
  REQUIRE(animator.character().Speak(line.phonemes, facerig::Seconds(0.2)) == facerig::CharacterError::kNone);
  animator.character().SetEmotion(facerig::Emotion::kJoy, 0.5f);

  std::vector<glm::vec3> positions(rig.vertex_count()), normals(rig.vertex_count());
  std::vector<double> frame_max_angle;
  std::vector<double> written_fraction;
  const int frames = static_cast<int>((0.4 + line.audio_duration().count()) * 60.0);
  for (int frame = 0; frame < frames; ++frame) {
    animator.Update(frame / 60.0);
    const facerig::BlendJob whole{&rig, animator.weights(), facerig::NormalMode::kRecompute, positions, normals};
    REQUIRE(whole.Run() == facerig::BlendJobError::kNone);
    INFO("frame " << frame);
    REQUIRE(std::memcmp(animator.positions().data(), positions.data(), positions.size() * sizeof(glm::vec3)) == 0);
    double worst = 0.0;
    for (std::size_t v = 0; v < normals.size(); ++v) worst = std::max(worst, AngleDegrees(animator.normals()[v], normals[v]));
    frame_max_angle.push_back(worst);
    written_fraction.push_back(static_cast<double>(animator.last_blend_work().moved_vertices) /
                               static_cast<double>(rig.vertex_count()));
  }
  std::sort(frame_max_angle.begin(), frame_max_angle.end());
  std::sort(written_fraction.begin(), written_fraction.end());
  const double p99 = frame_max_angle[frame_max_angle.size() * 99 / 100];
  WARN(frames << " frames: normals against the whole-mesh recomputed ones, max " << frame_max_angle.back()
              << " deg, p99 of the per-frame max " << p99 << " deg; positions written per frame, median "
              << 100.0 * written_fraction[written_fraction.size() / 2] << " % of the vertices");
  REQUIRE(frame_max_angle.back() == 0.0);  // the same bits
  // Speech moves the lower face only: most of the head is never written.
  REQUIRE(written_fraction[written_fraction.size() / 2] < 0.6);
  REQUIRE(written_fraction.back() > 0.0);
}
