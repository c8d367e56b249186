#include "facerig/runtime/character.h"

#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "measure/allocation_counter.h"
#include "support/test_meshes.h"

using facerig::Character;
using facerig::CharacterError;
using facerig::CharacterRig;
using facerig::Phoneme;
using facerig::Seconds;
using facerig::Viseme;
using facerig::test::MakePhoneme;

namespace {

// A small rig whose shapes carry the ARKit names the mappings look for.
facerig::Rig MakeArkitGridRig() {
  const std::vector<std::string> names = {
      "jawOpen",        "mouthClose",     "mouthFunnel",     "mouthPucker",      "mouthPress_L",
      "mouthPress_R",   "mouthRollLower", "mouthRollUpper",  "mouthSmile_L",     "mouthSmile_R",
      "mouthStretch_L", "mouthStretch_R", "mouthUpperUp_L",  "mouthUpperUp_R",   "mouthLowerDown_L",
      "mouthLowerDown_R", "eyeBlink_L",   "eyeBlink_R",      "cheekSquint_L",    "cheekSquint_R",
      "browInnerUp_L",  "browInnerUp_R",  "eyeWide_L",       "eyeWide_R",        "eyeLookIn_L",
      "eyeLookOut_L",   "eyeLookUp_L",    "eyeLookDown_L",   "eyeLookIn_R",      "eyeLookOut_R",
      "eyeLookUp_R",    "eyeLookDown_R"};
  return facerig::test::MakeNamedGridRig(names, 12);
}

// "a pa ba ma": open vowels around short bilabials (espeak-ng en-us names).
std::vector<Phoneme> OpenVowelsAroundBilabials() {
  return {MakePhoneme(0.00, 0.10, "_:"), MakePhoneme(0.10, 0.12, "a#"), MakePhoneme(0.22, 0.04, "p"),
          MakePhoneme(0.26, 0.12, "A:"), MakePhoneme(0.38, 0.03, "b"), MakePhoneme(0.41, 0.12, "A:"),
          MakePhoneme(0.53, 0.05, "m"),  MakePhoneme(0.58, 0.15, "A:"), MakePhoneme(0.73, 0.20, "_:")};
}

float Weight(const facerig::Rig& rig, const Character& character, const char* name) {
  return character.weights()[*rig.FindShape(name)];
}

}  // namespace

TEST_CASE("Character: p/b/m close the lips between open vowels", "[character]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  Character character(character_rig);
  const std::vector<Phoneme> line = OpenVowelsAroundBilabials();
  REQUIRE(character.Speak(line, Seconds(1.0)) == CharacterError::kNone);

  // Scan the line at 1 ms: each bilabial's interval (shifted by the stop
  // closure for p) holds an instant with full PP and no jaw opening.
  for (std::size_t i : {2u, 4u, 6u}) {
    float best_pp = 0.0f;
    float jaw_at_best = 1.0f;
    const double start = line[i].start.count(), end = start + line[i].duration.count();
    for (double t = start - 0.06; t <= end + 1e-9; t += 0.001) {
      REQUIRE(character.Update(Seconds(1.0 + t)) == CharacterError::kNone);
      const float pp = character.viseme_weights()[static_cast<std::size_t>(Viseme::kPP)];
      if (pp > best_pp) {
        best_pp = pp;
        jaw_at_best = Weight(rig, character, "jawOpen");
      }
    }
    INFO(line[i].symbol.view());
    REQUIRE(best_pp == Approx(1.0f));
    REQUIRE(jaw_at_best < 0.05f);
  }
  // The open vowels open the jaw.
  REQUIRE(character.Update(Seconds(1.0 + 0.32)) == CharacterError::kNone);
  REQUIRE(Weight(rig, character, "jawOpen") > 0.2f);
  REQUIRE(character.talking());
  REQUIRE(character.current_phoneme() != nullptr);
  REQUIRE(character.current_phoneme()->symbol.view() == "A:");
  // After the line the mouth rests.
  REQUIRE(character.Update(Seconds(1.0 + 2.0)) == CharacterError::kNone);
  REQUIRE(Weight(rig, character, "jawOpen") < 1e-3f);
  REQUIRE_FALSE(character.talking());
}

TEST_CASE("Character: smiling does not stop the lips closing on p", "[character]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  Character character(character_rig);
  character.SetEmotion(facerig::Emotion::kJoy, 1.0f);
  for (double t = 0.0; t < 2.0; t += 1.0 / 60) REQUIRE(character.Update(Seconds(t)) == CharacterError::kNone);
  REQUIRE(Weight(rig, character, "mouthSmile_L") > 0.3f);
  const std::vector<Phoneme> line = OpenVowelsAroundBilabials();
  REQUIRE(character.Speak(line, Seconds(2.0)) == CharacterError::kNone);
  float best_pp = 0.0f;
  for (double t = 0.18; t < 0.27; t += 0.001) {
    REQUIRE(character.Update(Seconds(2.0 + t)) == CharacterError::kNone);
    best_pp = std::max(best_pp, character.viseme_weights()[static_cast<std::size_t>(Viseme::kPP)]);
  }
  REQUIRE(best_pp == Approx(1.0f));
  REQUIRE(Weight(rig, character, "mouthSmile_L") > 0.3f);  // still smiling
}

TEST_CASE("Character: Speak and Update allocate nothing", "[character][allocation]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  Character character(character_rig);
  const std::vector<Phoneme> line = OpenVowelsAroundBilabials();
  facerig::test::AllocationCounter counter;
  REQUIRE(character.Speak(line, Seconds(0.0)) == CharacterError::kNone);
  character.SetEmotion(facerig::Emotion::kSurprise, 0.7f);
  for (double t = 0.0; t < 3.0; t += 1.0 / 60) REQUIRE(character.Update(Seconds(t)) == CharacterError::kNone);
  REQUIRE(character.Speak(line, Seconds(3.0)) == CharacterError::kNone);  // a new line replaces the old
  for (double t = 3.0; t < 5.0; t += 1.0 / 60) REQUIRE(character.Update(Seconds(t)) == CharacterError::kNone);
  REQUIRE(counter.count() == 0);
}

TEST_CASE("Character: deterministic for a seed, blinks at rest", "[character]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  facerig::CharacterParams params;
  params.seed = 7;
  Character a(character_rig, params), b(character_rig, params);
  params.seed = 8;
  Character c(character_rig, params);
  bool differs = false;
  float max_blink = 0.0f;
  for (double t = 0.0; t < 30.0; t += 1.0 / 60) {
    REQUIRE(a.Update(Seconds(t)) == CharacterError::kNone);
    REQUIRE(b.Update(Seconds(t)) == CharacterError::kNone);
    REQUIRE(c.Update(Seconds(t)) == CharacterError::kNone);
    REQUIRE(a.blink_left() == b.blink_left());
    differs = differs || a.blink_left() != c.blink_left();
    max_blink = std::max(max_blink, Weight(rig, a, "eyeBlink_L"));
  }
  REQUIRE(differs);
  REQUIRE(max_blink > 0.9f);  // ~8 blinks expected in 30 s at rest
}

TEST_CASE("Character: bad input is refused or safe", "[character][malformed]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  facerig::CharacterParams params;
  params.key_capacity = 24;  // room for the 9-phoneme line, not for 40
  Character character(character_rig, params);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  REQUIRE(character.Update(Seconds(nan)) == CharacterError::kNonFiniteTime);
  REQUIRE(character.Update(Seconds(std::numeric_limits<double>::infinity())) == CharacterError::kNonFiniteTime);
  REQUIRE(character.Speak(OpenVowelsAroundBilabials(), Seconds(nan)) == CharacterError::kNonFiniteTime);

  std::vector<Phoneme> bad = OpenVowelsAroundBilabials();
  bad[3].start = Seconds(0.01);  // backwards
  REQUIRE(character.Speak(bad, Seconds(0.0)) == CharacterError::kInvalidPhoneme);
  bad = OpenVowelsAroundBilabials();
  bad[2].duration = Seconds(nan);
  REQUIRE(character.Speak(bad, Seconds(0.0)) == CharacterError::kInvalidPhoneme);

  std::vector<Phoneme> long_line;
  for (int i = 0; i < 40; ++i) long_line.push_back(MakePhoneme(0.1 * i, 0.1, i % 2 ? "p" : "a#"));
  REQUIRE(character.Speak(long_line, Seconds(0.0)) == CharacterError::kTooManyKeys);
  REQUIRE(character.keys().empty());  // nothing changed

  // Time going backwards (a seek) is accepted; the character is not stuck.
  REQUIRE(character.Speak(OpenVowelsAroundBilabials(), Seconds(0.0)) == CharacterError::kNone);
  REQUIRE(character.Update(Seconds(0.5)) == CharacterError::kNone);
  REQUIRE(character.Update(Seconds(0.2)) == CharacterError::kNone);
  REQUIRE(character.Update(Seconds(5.0)) == CharacterError::kNone);
  REQUIRE(character.Update(Seconds(6.0)) == CharacterError::kNone);
  for (float w : character.weights()) REQUIRE(std::isfinite(w));
}

TEST_CASE("Character: a rig without ARKit shapes degrades with warnings", "[character]") {
  const facerig::Rig rig = facerig::test::MakeGridRig(4, 2);
  const CharacterRig character_rig = CharacterRig::Build(rig);
  REQUIRE_FALSE(character_rig.warnings().empty());
  Character character(character_rig);
  REQUIRE(character.Speak(OpenVowelsAroundBilabials(), Seconds(0.0)) == CharacterError::kNone);
  for (double t = 0.0; t < 1.0; t += 1.0 / 60) REQUIRE(character.Update(Seconds(t)) == CharacterError::kNone);
  for (float w : character.weights()) REQUIRE(w == 0.0f);
}

TEST_CASE("Character: idle gaze moves the eyeLook shapes, deterministically for a seed", "[character][gaze]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  REQUIRE(character_rig.gaze_shapes().has_value());
  facerig::CharacterParams params;
  params.seed = 9;
  Character a(character_rig, params), b(character_rig, params);
  params.gaze.enabled = false;
  Character still(character_rig, params);
  bool looked = false;
  for (double t = 0.0; t < 10.0; t += 1.0 / 60) {
    REQUIRE(a.Update(Seconds(t)) == CharacterError::kNone);
    REQUIRE(b.Update(Seconds(t)) == CharacterError::kNone);
    REQUIRE(still.Update(Seconds(t)) == CharacterError::kNone);
    for (const char* name : facerig::kGazeShapeNames) {
      REQUIRE(Weight(rig, a, name) == Weight(rig, b, name));
      REQUIRE(Weight(rig, still, name) == 0.0f);
      looked = looked || Weight(rig, a, name) > 0.05f;
    }
    // The gaze the weights came from: looking right turns the left eye in.
    const facerig::Gaze gaze = a.gaze();
    if (gaze.x > 0.2f) REQUIRE(Weight(rig, a, "eyeLookIn_L") > 0.0f);
  }
  REQUIRE(looked);
}


TEST_CASE("Character: phonemes pushed one by one give the weights Speak gives, without allocating",
          "[character][streaming]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  Character whole(character_rig), pushed(character_rig);
  const std::vector<Phoneme> line = OpenVowelsAroundBilabials();
  REQUIRE(whole.Speak(line, Seconds(0.5)) == CharacterError::kNone);
  facerig::test::AllocationCounter counter;
  REQUIRE(pushed.BeginLine(Seconds(0.5)) == CharacterError::kNone);
  for (const Phoneme& phoneme : line) REQUIRE(pushed.PushPhoneme(phoneme) == CharacterError::kNone);
  REQUIRE(pushed.EndLine() == CharacterError::kNone);
  for (double t = 0.0; t < 2.0; t += 1.0 / 60) {
    REQUIRE(whole.Update(Seconds(t)) == CharacterError::kNone);
    REQUIRE(pushed.Update(Seconds(t)) == CharacterError::kNone);
    for (std::size_t s = 0; s < rig.shape_count(); ++s) REQUIRE(pushed.weights()[s] == whole.weights()[s]);
  }
  REQUIRE(counter.count() == 0);
}

TEST_CASE("Character: a pushed phoneme shows once the next one arrives, and misuse is refused",
          "[character][streaming][malformed]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  Character character(character_rig);
  const std::vector<Phoneme> line = OpenVowelsAroundBilabials();
  REQUIRE(character.PushPhoneme(line[0]) == CharacterError::kNoOpenLine);
  REQUIRE(character.EndLine() == CharacterError::kNoOpenLine);
  REQUIRE(character.BeginLine(Seconds(0.0)) == CharacterError::kNone);
  for (std::size_t i = 0; i <= 2; ++i) REQUIRE(character.PushPhoneme(line[i]) == CharacterError::kNone);
  // The open "a" (line[1]) is keyed once "p" arrived: the jaw opens during it.
  REQUIRE(character.Update(Seconds(0.17)) == CharacterError::kNone);
  REQUIRE(Weight(rig, character, "jawOpen") > 0.1f);
  REQUIRE(character.PushPhoneme(line[0]) == CharacterError::kInvalidPhoneme);  // backwards
  REQUIRE(character.keys().size() > 0);                                           // the line is kept
  REQUIRE(character.EndLine() == CharacterError::kNone);
  REQUIRE(character.PushPhoneme(line[3]) == CharacterError::kNoOpenLine);  // ended
}

TEST_CASE("Character: blinks and gaze can be switched off", "[character][gaze]") {
  const facerig::Rig rig = MakeArkitGridRig();
  const CharacterRig character_rig = CharacterRig::Build(rig);
  Character character(character_rig);
  character.SetBlinking(false);
  character.SetGazing(false);
  for (double t = 0.0; t < 30.0; t += 1.0 / 60) {
    REQUIRE(character.Update(Seconds(t)) == CharacterError::kNone);
    for (const char* name : {"eyeBlink_L", "eyeBlink_R", "eyeLookIn_L", "eyeLookUp_R"}) {
      REQUIRE(Weight(rig, character, name) == 0.0f);
    }
  }
}
