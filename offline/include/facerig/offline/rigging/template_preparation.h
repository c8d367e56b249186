// The part of a build that depends on the template alone, done once for any
// number of targets (a cast built from one template: `facerig build` with
// several targets): the template with its synthesised tongueOut and its lid
// and lip margins (the caller resolves its landmark vertices and loads dlib
// once). BuildRig(const TemplatePreparation&, ...) builds one target from it;
// the results are byte for byte those of BuildRig on the template itself.
//
// Two variants, each prepared when first asked for and then kept: the
// template with the synthesised tongueOut (most targets), and the template as
// given (a target with a tongueOut of its own keeps it, so the synthesised
// shape is dropped for it, not made again).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "facerig/offline/openings/openings.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/rigging/rig_build.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

// One variant of the prepared template.
struct PreparedTemplate {
  const Rig* rig = nullptr;  // the given template, or the one with the synthesised tongueOut
  // The part tongueOut was synthesised from; empty: the template as given.
  std::string tongue_out_synthesised_from;
  // The expressions' lid and lip margins, kept to the descriptor's rims
  // (BuildRigParams::align_margins_to_openings; else empty).
  std::vector<OpeningMargin> margins;
};

class TemplatePreparation {
 public:
  // template_rig and info must outlive this object (they are kept by
  // reference). params: those of the builds (the openings, the tongueOut and
  // margin switches are read here).
  // \throw InvalidInputError when the template has no blend shapes or the
  //        descriptor's region does not fit it.
  TemplatePreparation(const Rig& template_rig, const FaceTemplateInfo& info, const BuildRigParams& params);
  ~TemplatePreparation();
  TemplatePreparation(TemplatePreparation&&) noexcept;
  TemplatePreparation& operator=(TemplatePreparation&&) noexcept;

  const Rig& template_rig() const { return *template_rig_; }
  const FaceTemplateInfo& info() const { return *info_; }
  std::uint32_t region_vertex_count() const { return info_->region.last + 1; }

  // The variant a target builds from: the template with the synthesised
  // tongueOut, unless the target has a tongueOut of its own (any spelling)
  // or none could be made (BuildRigParams::synthesise_tongue_out). Thread-safe.
  // \throw InvalidInputError as WithSynthesisedTongueOut.
  const PreparedTemplate& For(const RawRig& target) const;
  const PreparedTemplate& For(bool target_has_tongue_out) const;

 private:
  struct State;
  const Rig* template_rig_;
  const FaceTemplateInfo* info_;
  std::unique_ptr<State> state_;
};

// BuildRig and BuildRigOnRegistration (rig_build.h) from a template
// prepared once for many targets, made with the same params: the same
// results, the template's own work not done again.
BuildRigResult BuildRig(const TemplatePreparation& prepared, RawRig target, const RegistrationLandmarks& landmarks,
                        const BuildRigParams& params = {});
BuildRigResult BuildRig(const TemplatePreparation& prepared, BuildTarget target, const RegistrationLandmarks& landmarks,
                        const BuildRigParams& params = {});
BuildRigResult BuildRigOnRegistration(const TemplatePreparation& prepared, RawRig target,
                                      NonrigidIcpResult registered, const BuildRigParams& params = {});

}  // namespace facerig
