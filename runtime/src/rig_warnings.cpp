#include "facerig/runtime/rig_warnings.h"

#include "facerig/runtime/shape_names.h"
#include "facerig/runtime/speech/viseme_mapping.h"

namespace facerig {

std::vector<RigWarning> SpeechAndBlinkWarnings(const Rig& rig) {
  std::vector<RigWarning> warnings;
  // The same mapping a Character builds: when it moves nothing, speech leaves the face at rest.
  if (BuildVisemeMapping(rig).mapping.empty()) {
    warnings.push_back({std::string(kCannotSpeak),
                        "the rig cannot speak: it has no mouth, jaw or viseme shapes (e.g. jawOpen, mouthClose, "
                        "viseme_aa), so speech leaves the face still"});
  }
  // Each eye blinks on its own shape; with neither there is no blink at all.
  if (FindShapesByArkitName(rig, "eyeBlink_L").empty() && FindShapesByArkitName(rig, "eyeBlink_R").empty()) {
    warnings.push_back({std::string(kCannotBlink),
                        "the rig cannot blink: it has no blink shapes (eyeBlink_L, eyeBlink_R)"});
  }
  return warnings;
}

}  // namespace facerig
