#include "facerig/runtime/behaviour/emotion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/shape_mapping_files.h"
#include "facerig/runtime/rig_builder.h"
#include "facerig/runtime/speech/coarticulation.h"
#include "facerig/runtime/speech/viseme_mapping.h"
#include "measure/allocation_counter.h"
#include "support/test_meshes.h"

namespace facerig {
using test::Key;

namespace {

constexpr std::size_t Index(Emotion e) { return static_cast<std::size_t>(e); }

// Emotions over speech as Character layers them: EmotionChannelsJob, then
// CombineChannelsJob with the speech as base. Channel storage sized once.
struct EmotionLayer {
  explicit EmotionLayer(const facerig::EmotionRig& rig) : emotions(&rig), values(rig.channel_count()) {}

  // The emotion job's error, or kNone and the combine's error in *combined.
  EmotionChannelsJobError Run(std::span<const float> intensities, float lip_contact, std::span<const float> speech,
                              std::span<float> out, CombineChannelsError* combined = nullptr) {
    const EmotionChannelsJobError error = EmotionChannelsJob{emotions, intensities, lip_contact, values}.Run();
    if (error != EmotionChannelsJobError::kNone) return error;
    const ChannelLayer layer{ChannelRule::kAdd, values};
    const CombineChannelsError combine = CombineChannelsJob{speech, std::span(&layer, 1), 0.0f, out}.Run();
    if (combined != nullptr) *combined = combine;
    return error;
  }

  const facerig::EmotionRig* emotions;
  std::vector<ChannelValue> values;
};

CombineChannelsError LayerEmotions(const facerig::EmotionRig& rig, std::span<const float> intensities,
                                   float lip_contact, std::span<const float> speech, std::span<float> out) {
  EmotionLayer layer(rig);
  CombineChannelsError combined = CombineChannelsError::kInvalidValue;
  if (layer.Run(intensities, lip_contact, speech, out, &combined) != EmotionChannelsJobError::kNone) {
    return CombineChannelsError::kInvalidValue;
  }
  return combined;
}

facerig::Rig NamedRig(const std::vector<std::string>& names) { return facerig::test::MakeNamedGridRig(names); }

// --- Mouth geometry of ICT-FaceKit ------------------------------------------
// Inner-lip midline vertices near dlib landmarks 62 (upper inner lip centre)
// and 66 (lower), split into upper and lower lip by whether jawOpen carries
// them; the upper incisor edge; and the lower lip's midline cross-section.
struct IctMouth {
  std::uint32_t landmark_upper = 0, landmark_lower = 0;
  std::vector<std::uint32_t> upper_lip, lower_lip;
  std::vector<std::uint32_t> incisor_edge;
  // Ordered outline of the lower lip in the midline (sagittal) plane: the
  // outer surface from the lip contact down to the chin crease, back up the
  // inner (mucosal) surface. ICT vertex indices, read off the neutral mesh.
  std::vector<std::uint32_t> lower_lip_section = {5519, 5517, 5515, 5516, 5514, 5945, 5518,
                                                  11261, 6632, 5512, 5521, 5537, 5536, 5538};
};

std::vector<int> LandmarkVertices() {
  const std::string text = facerig::ReadFileText(facerig::test::IctDir() / "vertex_indices.json");
  std::size_t at = text.find("\"idx_to_landmark_verts\"");
  REQUIRE(at != std::string::npos);
  at = text.find('[', at);
  const std::size_t end = text.find(']', at);
  std::vector<int> out;
  for (std::size_t i = at + 1; i < end;) {
    while (i < end && !std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
    if (i >= end) break;
    out.push_back(std::stoi(text.substr(i)));
    while (i < end && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
  }
  REQUIRE(out.size() == 68);
  return out;
}

std::vector<glm::vec3> DenseDeltas(const facerig::Rig& rig, const std::string& name) {
  std::vector<glm::vec3> dense(rig.vertex_count(), glm::vec3(0.0f));
  const facerig::BlendShapeView shape = rig.shape(*rig.FindShape(name));
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
    dense[shape.vertex_indices[i]] = shape.position_deltas[i];
  }
  return dense;
}

const IctMouth& Mouth() {
  static const IctMouth mouth = [] {
    const facerig::Rig& rig = facerig::test::IctRig();
    const auto neutral = rig.positions();
    const std::vector<int> landmarks = LandmarkVertices();
    IctMouth m;
    m.landmark_upper = static_cast<std::uint32_t>(landmarks[62]);
    m.landmark_lower = static_cast<std::uint32_t>(landmarks[66]);
    const std::vector<glm::vec3> jaw = DenseDeltas(rig, "jawOpen");
    const float lower_motion = glm::length(jaw[m.landmark_lower]);
    const facerig::Part* face = rig.FindPart("M_Face");
    REQUIRE(face != nullptr);
    for (std::uint32_t v = face->first_vertex; v < face->first_vertex + face->vertex_count; ++v) {
      if (std::abs(neutral[v].x) > 1e-4f) continue;
      const float d = std::min(glm::distance(neutral[v], neutral[m.landmark_upper]),
                               glm::distance(neutral[v], neutral[m.landmark_lower]));
      if (d > 0.25f) continue;
      (glm::length(jaw[v]) > 0.5f * lower_motion ? m.lower_lip : m.upper_lip).push_back(v);
    }
    const facerig::Part* teeth = rig.FindPart("M_Teeth");
    REQUIRE(teeth != nullptr);
    std::vector<std::uint32_t> front;
    float max_z = -1e30f;
    for (std::uint32_t v = teeth->first_vertex; v < teeth->first_vertex + teeth->vertex_count; ++v) {
      if (glm::length(jaw[v]) > 0.0f || std::abs(neutral[v].x) > 0.1f) continue;  // upper teeth, centre
      front.push_back(v);
      max_z = std::max(max_z, neutral[v].z);
    }
    float min_y = 1e30f;
    for (std::uint32_t v : front) {
      if (neutral[v].z > max_z - 0.1f) min_y = std::min(min_y, neutral[v].y);
    }
    for (std::uint32_t v : front) {
      if (neutral[v].z > max_z - 0.1f && neutral[v].y < min_y + 0.01f) m.incisor_edge.push_back(v);
    }
    return m;
  }();
  return mouth;
}

struct MouthMeasure {
  float aperture = 0.0f;      // closest upper-lower inner-lip midline distance
  float landmark_gap = 0.0f;  // |landmark 62 - landmark 66|
  float lip_teeth = 0.0f;     // upper incisor edge to the lower lip's section; 0 when inside it
};

float SegmentDistance(glm::vec2 p, glm::vec2 a, glm::vec2 b) {
  const glm::vec2 ab = b - a;
  const float t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
  return glm::length(p - (a + t * ab));
}

MouthMeasure Measure(std::span<const glm::vec3> p) {
  const IctMouth& m = Mouth();
  MouthMeasure out;
  out.aperture = 1e30f;
  for (std::uint32_t u : m.upper_lip) {
    for (std::uint32_t l : m.lower_lip) out.aperture = std::min(out.aperture, glm::distance(p[u], p[l]));
  }
  out.landmark_gap = glm::distance(p[m.landmark_upper], p[m.landmark_lower]);
  glm::vec3 edge(0.0f);
  for (std::uint32_t v : m.incisor_edge) edge += p[v];
  edge /= static_cast<float>(m.incisor_edge.size());
  const glm::vec2 e(edge.y, edge.z);
  std::vector<glm::vec2> section;
  for (std::uint32_t v : m.lower_lip_section) section.emplace_back(p[v].y, p[v].z);
  bool inside = false;
  float distance = 1e30f;
  for (std::size_t i = 0; i < section.size(); ++i) {
    const glm::vec2 a = section[i], b = section[(i + 1) % section.size()];
    distance = std::min(distance, SegmentDistance(e, a, b));
    if ((a.x > e.x) != (b.x > e.x) && e.y < a.y + (e.x - a.x) * (b.y - a.y) / (b.x - a.x)) inside = !inside;
  }
  out.lip_teeth = inside ? 0.0f : distance;
  return out;
}

// The full per-frame stack for one set of viseme weights and emotion intensities.
struct IctStack {
  const facerig::Rig& rig = facerig::test::IctRig();
  facerig::VisemeMappingResult mapping = facerig::BuildVisemeMapping(rig);
  facerig::EmotionRigResult emotions = facerig::BuildEmotionRig(rig);
  std::vector<float> speech = std::vector<float>(rig.shape_count());
  std::vector<float> weights = std::vector<float>(rig.shape_count());
  std::vector<glm::vec3> positions = std::vector<glm::vec3>(rig.vertex_count());

  MouthMeasure Pose(const facerig::VisemeWeights& visemes, const std::array<float, facerig::kEmotionCount>& emo,
                    bool protect_contact = true) {
    facerig::VisemeWeightsJob speech_job{&mapping.mapping, visemes, 1.0f, 1.0f, false, speech};
    REQUIRE(speech_job.Run() == facerig::VisemeWeightsJobError::kNone);
    REQUIRE(LayerEmotions(emotions.emotions, emo, protect_contact ? facerig::LipContactWeight(visemes) : 0.0f,
                          speech, weights) == CombineChannelsError::kNone);
    facerig::BlendJob blend{&rig, weights, facerig::NormalMode::kNone, positions, {}};
    REQUIRE(blend.Run() == facerig::BlendJobError::kNone);
    return Measure(positions);
  }
};

facerig::VisemeWeights OneHot(Viseme v) {
  facerig::VisemeWeights w{};
  w[static_cast<std::size_t>(v)] = 1.0f;
  return w;
}

}  // namespace

TEST_CASE("Emotion names and lip-opening shapes", "[emotion]") {
  for (std::size_t e = 0; e < facerig::kEmotionCount; ++e) {
    REQUIRE(facerig::ParseEmotion(facerig::ToString(static_cast<Emotion>(e))) == static_cast<Emotion>(e));
  }
  REQUIRE_FALSE(facerig::ParseEmotion("contempt"));
  for (const char* name : {"jawOpen", "jawLeft", "jaw_R", "mouthPress_L", "mouthUpperUpLeft", "mouthLowerDown_R", "noseSneer_L",
                           "mouthFunnel", "blendShape1.mouthShrugUpper", "mouthRollLower"}) {
    INFO(name);
    REQUIRE(facerig::OpensLips(name));
  }
  for (const char* name : {"mouthSmileLeft", "mouthSmile_R", "mouthStretch_L", "eyeBlinkLeft", "mouthLeft",
                           "cheekSquint_L", "mouthDimpleRight", "mouthFrown_L", "browInnerUp"}) {
    INFO(name);
    REQUIRE_FALSE(facerig::OpensLips(name));
  }
}

TEST_CASE("BuildEmotionRig degrades on rigs missing shapes", "[emotion]") {
  const facerig::Rig rig = NamedRig({"mouthSmileLeft", "mouthSmileRight", "jawOpen", "browInnerUp"});
  const facerig::EmotionRigResult result = facerig::BuildEmotionRig(rig);
  const auto joy = result.emotions.contributions(Emotion::kJoy);
  REQUIRE(joy.size() == 2);
  REQUIRE(joy[0].weight == Approx(0.8f));
  REQUIRE_FALSE(joy[0].opens_lips);
  const auto surprise = result.emotions.contributions(Emotion::kSurprise);
  REQUIRE(surprise.size() == 2);  // browInnerUp and jawOpen
  for (const auto& c : surprise) REQUIRE(c.opens_lips == (rig.shape_name(c.shape) == "jawOpen"));
  auto mentions = [&](const std::string& text) {
    return std::any_of(result.warnings.begin(), result.warnings.end(),
                       [&](const std::string& w) { return w.find(text) != std::string::npos; });
  };
  REQUIRE(mentions("cheekSquint_L"));
  REQUIRE(mentions("noseSneer_R"));
  REQUIRE_FALSE(mentions("mouthSmile_L"));

  const facerig::Rig blank = facerig::test::MakeGridRig(4, 2);
  const facerig::EmotionRigResult none = facerig::BuildEmotionRig(blank);
  REQUIRE(none.emotions.empty());
  REQUIRE(none.emotions.rig_shape_count() == 2);
  REQUIRE_FALSE(none.warnings.empty());
}

TEST_CASE("Emotion overrides from JSON", "[emotion]") {
  const facerig::Rig rig = NamedRig({"mouthSmile_L", "mouthSmile_R", "jawOpen", "mouthFrown_L"});
  const facerig::EmotionOverrides overrides = facerig::ParseEmotionJson(
      R"({"joy": {"mouthSmile_L": 1.0, "jawOpen": {"weight": 0.2, "opens_lips": false}}, "anger": {}})", "emo");
  const facerig::EmotionRigResult result = facerig::BuildEmotionRig(rig, &overrides);
  const auto joy = result.emotions.contributions(Emotion::kJoy);
  REQUIRE(joy.size() == 2);
  for (const auto& c : joy) {
    if (rig.shape_name(c.shape) == "jawOpen") {
      REQUIRE(c.weight == Approx(0.2f));
      REQUIRE_FALSE(c.opens_lips);  // the file says so
    } else {
      REQUIRE(c.weight == 1.0f);
    }
  }
  REQUIRE(result.emotions.contributions(Emotion::kAnger).empty());
  REQUIRE_FALSE(result.emotions.contributions(Emotion::kSadness).empty());  // built-in kept

  auto error_of = [](const std::string& text) -> std::string {
    try {
      facerig::ParseEmotionJson(text, "emo.json");
    } catch (const facerig::IoError& e) {
      REQUIRE(e.path() == "emo.json");
      return e.message();
    }
    return "no error";
  };
  REQUIRE(error_of("nope").find("not valid JSON") != std::string::npos);
  REQUIRE(error_of(R"({"contempt": {}})").find("contempt") != std::string::npos);
  REQUIRE(error_of(R"({"joy": {"mouthSmile_L": -0.5}})").find("joy.mouthSmile_L") != std::string::npos);
  REQUIRE(error_of(R"({"joy": {"jawOpen": {"weight": 0.1, "opens_lips": 1}}})").find("joy.jawOpen.opens_lips") !=
          std::string::npos);
  const std::filesystem::path path = facerig::test::OutputPath("emotions_bad.json");
  facerig::WriteFileAtomically(path, std::string_view(R"({"fear": {"eyeWide_L": "wide"}})"));
  try {
    facerig::ReadEmotionFile(path);
    FAIL("expected an IoError");
  } catch (const facerig::IoError& e) {
    REQUIRE(std::string(e.what()).find(path.string()) != std::string::npos);
    REQUIRE(e.message().find("fear.eyeWide_L") != std::string::npos);
  }
}

TEST_CASE("EmotionState attack and release", "[emotion]") {
  facerig::EmotionState state;
  state.attack[Index(Emotion::kJoy)] = 0.4f;
  state.release[Index(Emotion::kJoy)] = 0.8f;
  state.SetTarget(Emotion::kJoy, 1.0f);
  state.SetTarget(Emotion::kSurprise, 2.0f);  // clamped
  REQUIRE(state.target[Index(Emotion::kSurprise)] == 1.0f);
  state.SetTarget(Emotion::kFear, std::numeric_limits<float>::quiet_NaN());  // ignored
  REQUIRE(state.target[Index(Emotion::kFear)] == 0.0f);

  facerig::test::AllocationCounter counter;
  REQUIRE(state.Advance(Seconds(0.1)));
  REQUIRE(state.intensity[Index(Emotion::kJoy)] == Approx(0.25f));
  for (int i = 0; i < 3; ++i) REQUIRE(state.Advance(Seconds(0.1)));
  REQUIRE(state.intensity[Index(Emotion::kJoy)] == Approx(1.0f));
  REQUIRE(state.Advance(Seconds(1.0)));
  REQUIRE(state.intensity[Index(Emotion::kJoy)] == 1.0f);  // stays at the target
  REQUIRE(state.intensity[Index(Emotion::kSurprise)] == 1.0f);
  REQUIRE(counter.count() == 0);

  state.SetTarget(Emotion::kJoy, 0.0f);
  REQUIRE(state.Advance(Seconds(0.2)));
  REQUIRE(state.intensity[Index(Emotion::kJoy)] == Approx(0.75f));  // release is slower
  REQUIRE(state.Advance(Seconds(10.0)));
  REQUIRE(state.intensity[Index(Emotion::kJoy)] == 0.0f);

  // Bad dt or times change nothing.
  state.SetTarget(Emotion::kAnger, 1.0f);
  const facerig::EmotionState before = state;
  REQUIRE_FALSE(state.Advance(Seconds(-0.1)));
  REQUIRE_FALSE(state.Advance(Seconds(std::numeric_limits<double>::quiet_NaN())));
  REQUIRE_FALSE(state.Advance(Seconds(std::numeric_limits<double>::infinity())));
  state.attack[Index(Emotion::kAnger)] = 0.0f;
  REQUIRE_FALSE(state.Advance(Seconds(0.1)));
  state.attack = before.attack;
  REQUIRE(state.intensity == before.intensity);
}

TEST_CASE("Emotion channels add, combine, clamp and protect lip contact", "[emotion]") {
  const facerig::Rig rig = NamedRig({"mouthSmile_L", "mouthSmile_R", "jawOpen", "eyeWide_L", "eyeWide_R",
                                     "browInnerUp", "browOuterUp_L", "browOuterUp_R"});
  const facerig::EmotionRigResult emotions = facerig::BuildEmotionRig(rig);
  const std::size_t smile = *rig.FindShape("mouthSmile_L");
  const std::size_t jaw = *rig.FindShape("jawOpen");
  const std::size_t wide = *rig.FindShape("eyeWide_L");
  std::array<float, facerig::kEmotionCount> intensity{};
  intensity[Index(Emotion::kJoy)] = 1.0f;
  intensity[Index(Emotion::kSurprise)] = 0.5f;
  intensity[Index(Emotion::kFear)] = 0.5f;
  std::vector<float> speech(rig.shape_count(), 0.0f), out(rig.shape_count(), -5.0f);
  speech[jaw] = 0.6f;
  speech[smile] = 0.5f;
  EmotionLayer layer(emotions.emotions);
  CombineChannelsError combined = CombineChannelsError::kInvalidValue;
  const auto run = [&](float lip_contact) {
    REQUIRE(layer.Run(intensity, lip_contact, speech, out, &combined) == EmotionChannelsJobError::kNone);
    REQUIRE(combined == CombineChannelsError::kNone);
  };
  run(0.0f);
  REQUIRE(out[smile] == 1.0f);                                    // 0.5 + 0.8, clamped
  REQUIRE(out[jaw] == Approx(0.6f + 0.5f * 0.25f + 0.5f * 0.15f));  // speech + surprise + fear
  REQUIRE(out[wide] == Approx(0.5f * 0.8f + 0.5f * 0.8f));          // several emotions sum...
  intensity[Index(Emotion::kSurprise)] = 1.0f;
  run(0.0f);
  REQUIRE(out[wide] == 1.0f);  // ...and clamp per shape

  // Full lip contact: the lip-opening emotion parts vanish, the smile stays.
  run(1.0f);
  REQUIRE(out[jaw] == Approx(0.6f));
  REQUIRE(out[smile] == 1.0f);
  run(0.5f);
  REQUIRE(out[jaw] == Approx(0.6f + 0.5f * (0.25f + 0.075f)));

  // In place.
  std::vector<float> in_place = speech;
  REQUIRE(LayerEmotions(emotions.emotions, intensity, 0.0f, in_place, in_place) == CombineChannelsError::kNone);
  REQUIRE(in_place[smile] == 1.0f);
  REQUIRE(in_place[jaw] == Approx(0.6f + 0.25f + 0.075f));

  facerig::test::AllocationCounter counter;
  for (int i = 0; i < 100; ++i) run(0.5f);
  REQUIRE(counter.count() == 0);
}

TEST_CASE("Emotion channels: invalid inputs", "[emotion]") {
  const facerig::Rig rig = NamedRig({"mouthSmile_L", "jawOpen"});
  const facerig::EmotionRigResult emotions = facerig::BuildEmotionRig(rig);
  std::array<float, facerig::kEmotionCount> intensity{};
  std::vector<float> speech(rig.shape_count(), 0.1f), out(rig.shape_count(), 0.5f);
  const std::vector<float> untouched = out;
  std::vector<ChannelValue> values(emotions.emotions.channel_count(), ChannelValue{0, 0.25f});
  const std::vector<ChannelValue> values_untouched = values;
  auto make = [&] { return EmotionChannelsJob{&emotions.emotions, intensity, 0.0f, values}; };
  EmotionChannelsJob job = make();
  job.emotions = nullptr;
  REQUIRE(job.Run() == EmotionChannelsJobError::kNoEmotions);
  job = make();
  job.intensities = std::span<const float>(intensity).first(5);
  REQUIRE(job.Run() == EmotionChannelsJobError::kIntensityCountMismatch);
  job.intensities = {};
  REQUIRE(job.Run() == EmotionChannelsJobError::kIntensityCountMismatch);
  job = make();
  job.lip_contact = std::numeric_limits<float>::quiet_NaN();
  REQUIRE(job.Run() == EmotionChannelsJobError::kInvalidIntensity);
  job = make();
  job.out_values = std::span(values).first(values.size() - 1);
  REQUIRE(job.Run() == EmotionChannelsJobError::kValueCountMismatch);
  intensity[2] = 1.5f;
  job = make();
  REQUIRE(job.Run() == EmotionChannelsJobError::kInvalidIntensity);
  intensity[2] = 0.0f;
  REQUIRE(values == values_untouched);
  REQUIRE(std::string(facerig::ToString(EmotionChannelsJobError::kInvalidIntensity)).find("lip_contact") !=
          std::string::npos);

  // The speech side is the combine's to check: sizes, then finiteness.
  REQUIRE(LayerEmotions(emotions.emotions, intensity, 0.0f, {}, out) == CombineChannelsError::kWeightCountMismatch);
  REQUIRE(LayerEmotions(emotions.emotions, intensity, 0.0f, speech, std::span<float>(out).first(1)) ==
          CombineChannelsError::kWeightCountMismatch);
  speech[1] = std::numeric_limits<float>::infinity();
  REQUIRE(LayerEmotions(emotions.emotions, intensity, 0.0f, speech, out) == CombineChannelsError::kInvalidValue);
  REQUIRE(out == untouched);
}

TEST_CASE("ICT-FaceKit: emotions resolve, and p/b/m and f/v survive every emotion (shared data)",
          "[emotion][shared-data]") {
  IctStack stack;
  REQUIRE(stack.mapping.warnings.empty());
  REQUIRE(stack.emotions.warnings.empty());
  for (std::size_t e = 0; e < facerig::kEmotionCount; ++e) {
    REQUIRE_FALSE(stack.emotions.emotions.contributions(static_cast<Emotion>(e)).empty());
  }
  const IctMouth& mouth = Mouth();
  REQUIRE(mouth.upper_lip.size() >= 2);
  REQUIRE(mouth.lower_lip.size() >= 2);
  REQUIRE(mouth.incisor_edge.size() >= 2);
  REQUIRE(std::find(mouth.lower_lip_section.begin(), mouth.lower_lip_section.end(), mouth.landmark_lower) !=
          mouth.lower_lip_section.end());

  const std::array<float, facerig::kEmotionCount> calm{};
  const MouthMeasure neutral = stack.Pose(facerig::VisemeWeights{}, calm);
  const MouthMeasure aa = stack.Pose(OneHot(Viseme::kAA), calm);
  const MouthMeasure pp = stack.Pose(OneHot(Viseme::kPP), calm);
  const MouthMeasure ff = stack.Pose(OneHot(Viseme::kFF), calm);
  std::printf("ICT mouth (rig units): aa aperture %.4f (landmarks %.4f); neutral %.4f (%.4f); "
              "PP %.4f (%.4f); FF lip-teeth %.4f, neutral lip-teeth %.4f\n",
              aa.aperture, aa.landmark_gap, neutral.aperture, neutral.landmark_gap, pp.aperture,
              pp.landmark_gap, ff.lip_teeth, neutral.lip_teeth);
  REQUIRE(aa.aperture > 0.05f * stack.rig.bounding_diagonal());
  REQUIRE(pp.aperture <= 0.05f * aa.aperture);
  REQUIRE(ff.lip_teeth <= 0.02f * aa.aperture);
  // The lip-teeth measure discriminates: at rest the lip is in front of the teeth.
  REQUIRE(neutral.lip_teeth > 0.04f * aa.aperture);
  REQUIRE(aa.lip_teeth > 0.5f * aa.aperture);

  struct Case {
    const char* name;
    std::array<float, facerig::kEmotionCount> intensity;
  };
  const Case cases[] = {
      {"joy", {1, 0, 0, 0, 0, 0}},     {"sadness", {0, 1, 0, 0, 0, 0}}, {"fear", {0, 0, 1, 0, 0, 0}},
      {"anger", {0, 0, 0, 1, 0, 0}},   {"surprise", {0, 0, 0, 0, 1, 0}}, {"disgust", {0, 0, 0, 0, 0, 1}},
      {"joy+surprise", {1, 0, 0, 0, 1, 0}}, {"fear+anger", {0, 0, 1, 1, 0, 0}},
  };
  for (const Case& c : cases) {
    const MouthMeasure with_pp = stack.Pose(OneHot(Viseme::kPP), c.intensity);
    const MouthMeasure with_ff = stack.Pose(OneHot(Viseme::kFF), c.intensity);
    const MouthMeasure unprotected = stack.Pose(OneHot(Viseme::kPP), c.intensity, /*protect_contact=*/false);
    std::printf("ICT %-12s PP aperture %.4f (%.1f%% of aa; %.1f%% without protection), "
                "FF lip-teeth %.4f (%.1f%% of aa)\n",
                c.name, with_pp.aperture, 100.0f * with_pp.aperture / aa.aperture,
                100.0f * unprotected.aperture / aa.aperture, with_ff.lip_teeth,
                100.0f * with_ff.lip_teeth / aa.aperture);
    INFO(c.name);
    REQUIRE(with_pp.aperture <= 0.05f * aa.aperture);
    REQUIRE(with_ff.lip_teeth <= 0.02f * aa.aperture);
  }
  // Without the protection a surprised jaw drop keeps the lips apart on "p".
  const MouthMeasure open_p = stack.Pose(OneHot(Viseme::kPP), {0, 0, 0, 0, 1, 0}, false);
  REQUIRE(open_p.aperture > 0.2f * aa.aperture);
}

TEST_CASE("ICT-FaceKit: a 30 ms p between aa closes the lips while smiling, end to end (shared data)",
          "[emotion][shared-data]") {
  IctStack stack;
  const std::array<float, facerig::kEmotionCount> joy = {1, 0, 0, 0, 0, 0};
  const facerig::CoarticulationParams params;
  for (double duration : {0.02, 0.03, 0.04}) {
    const double start = 1.0 + 0.007;  // off the frame grid
    const std::vector<facerig::VisemeKey> keys = {Key(start - 0.15, start, Viseme::kAA, 1.0f),
                                                  Key(start, start + duration, Viseme::kPP, 1.0f),
                                                  Key(start + duration, start + duration + 0.15, Viseme::kAA, 1.0f)};
    facerig::VisemeTrack track;
    REQUIRE(facerig::VisemeTrack::Make(keys, track) == facerig::VisemeTrackError::kNone);
    facerig::VisemeWeights visemes{};
    auto pose_at = [&](double t) {
      facerig::CoarticulationJob job{&track, facerig::Seconds(t), &params, &visemes};
      REQUIRE(job.Run() == facerig::CoarticulationError::kNone);
      return stack.Pose(visemes, joy);
    };
    const float open = pose_at(start - 0.1).aperture;  // inside the first aa
    const float centre = pose_at(start + 0.5 * duration).aperture;
    float best_frame = 1e30f;
    for (int f = 0; f < 200; ++f) {
      const double t = f / 60.0;
      if (t >= start && t <= start + duration) best_frame = std::min(best_frame, pose_at(t).aperture);
    }
    std::printf("ICT p of %.0f ms between aa, joy 1: aa %.4f, p centre %.4f (%.1f%%), best 60 fps frame %.4f\n",
                duration * 1000.0, open, centre, 100.0f * centre / open, best_frame);
    INFO("duration " << duration);
    REQUIRE(centre <= 0.05f * open);
    REQUIRE(best_frame <= 0.05f * open);
  }
}

}  // namespace facerig
