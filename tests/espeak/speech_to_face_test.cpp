// End to end: espeak-ng text -> phonemes -> Character -> ICT-FaceKit lips.
#include <algorithm>

#include <catch2/catch.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "measure/lip_probe.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/speech/phoneme_visemes.h"
#include "support/test_meshes.h"

TEST_CASE("espeak-ng speech closes the ICT lips on every p/b/m and opens them on vowels (shared data)",
          "[speech_to_face][shared-data]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  const auto lips = facerig::IctInnerLipVertices(facerig::test::IctDir());
  REQUIRE(lips);
  const facerig::LipProbe probe(rig, (*lips)[0], (*lips)[1]);
  const facerig::CharacterRig character_rig = facerig::CharacterRig::Build(rig);
  REQUIRE(character_rig.warnings().empty());
  facerig::EspeakPhonemeSource source;
  const facerig::CharacterParams params;

  std::size_t bilabials = 0;
  for (const char* text : {"Bob bought a map from a puppet maker.", "Maybe my mom bakes apple pie.",
                           "Pam, please bring the ember lamp by the big barn.",
                           "I am happy, but Tim moved the tub."}) {
    const facerig::SpeechLine line = source.Synthesize(text, "en-us");
    facerig::Character character(character_rig, params);
    REQUIRE(character.Speak(line.phonemes, facerig::Seconds(0.0)) == facerig::CharacterError::kNone);
    std::vector<float> aperture;
    for (double t = 0.0; t < line.audio_duration().count() + 0.5; t += 0.001) {
      REQUIRE(character.Update(facerig::Seconds(t)) == facerig::CharacterError::kNone);
      aperture.push_back(probe.Aperture(character.weights()));
    }
    const float widest = *std::max_element(aperture.begin(), aperture.end());
    INFO(text);
    REQUIRE(widest > 0.5f);  // cm: the mouth really opens while speaking
    REQUIRE(aperture.back() < 0.05f * widest);  // and rests after the line
    for (const facerig::Phoneme& phoneme : line.phonemes) {
      const auto map = facerig::LookupPhonemeVisemes(phoneme.language.view(), phoneme.symbol.view());
      if (!map || map->count == 0 || map->visemes[0] != facerig::Viseme::kPP) continue;
      ++bilabials;
      const bool stop = map->has(facerig::PhonemeVisemes::kUnvoicedStop);
      const double begin = phoneme.start.count() - (stop ? params.timing.stop_closure : 0.0);
      const double end = phoneme.start.count() + std::max(phoneme.duration.count(), params.timing.min_duration);
      float lowest = widest;
      for (double t = std::max(0.0, begin); t <= end; t += 0.001) {
        lowest = std::min(lowest, aperture[std::min(aperture.size() - 1, static_cast<std::size_t>(t * 1000.0 + 0.5))]);
      }
      INFO(phoneme.symbol.view() << " at " << phoneme.start.count() << " s");
      REQUIRE(lowest <= 0.05f * widest);
    }
  }
  REQUIRE(bilabials >= 20);
}
