// ARKit's tongueOut for a template that has a tongue but no such shape
// (ICT-FaceKit: its "gums_and_tongue" part, no tongueOut), made from the
// tongue's own geometry before the transfer, so that every rig built from it
// has all 52 ARKit names.
//
// The tongue: a part named "tongue" whole; in a part that holds the gums too,
// the UV chart of the part that the template's jawOpen carries, that does not
// hug the teeth (the gums do) and lies highest (the floor of the mouth lies
// lower). Its frame: forward from the tongue towards the chin (the skin
// vertex jawOpen moves most), across the up axis; along from its back (0) to
// its tip (1). The shape: the jaw a little open (a share of jawOpen) and the
// tongue stretched forward and lifted as along squared, so its tip ends past
// the lower front teeth and over their edge; what would end up inside the
// lower front teeth rests on their edge instead.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include <glm/vec3.hpp>

#include "facerig/offline/rigging/face_template.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

struct TongueOutParams {
  double jaw_share = 0.35;  // of the template's jawOpen
  // How far the tip ends in front of the lips (the foremost skin the jaw
  // carries), in tongue lengths.
  double overhang = 0.3;
  // How far above the lower front teeth's edge the tip ends, and the least
  // the tongue keeps above that edge over the teeth, in tongue lengths.
  double clearance = 0.12;
};

struct SynthesisedTongueOut {
  RawBlendShape shape;            // "tongueOut", on the template's vertices
  std::string part;               // the part the tongue was found in
  std::size_t tongue_vertices = 0;
  std::uint32_t tip_vertex = 0;   // the tongue's foremost vertex at rest
  double tongue_length = 0.0;     // back to tip along forward, template units
  glm::vec3 forward{0.0f};        // the tongue's frame (unit vectors)
  glm::vec3 up{0.0f};
  bool over_teeth = false;        // the lower front teeth were found and cleared
};

// nullopt when the template answers tongueOut already, has no part whose
// name says tongue, has no jawOpen, or its tongue has no length.
std::optional<SynthesisedTongueOut> SynthesiseTongueOut(const Rig& rig, const FaceTemplateInfo& info,
                                                        const TongueOutParams& params = {});

// The template with the synthesised tongueOut appended; nullopt as above.
std::optional<Rig> WithSynthesisedTongueOut(const Rig& rig, const FaceTemplateInfo& info,
                                            SynthesisedTongueOut* synthesised = nullptr,
                                            const TongueOutParams& params = {});

}  // namespace facerig
