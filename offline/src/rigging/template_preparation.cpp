#include "facerig/offline/rigging/template_preparation.h"

#include <algorithm>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "facerig/offline/openings/margins.h"
#include "facerig/offline/rigging/rig_build.h"
#include "facerig/offline/rigging/tongue_out.h"
#include "facerig/runtime/shape_names.h"

namespace facerig {
namespace {

// The expressions' margins, kept to the descriptor's rims where it lists them.
std::vector<OpeningMargin> DescribedMargins(std::vector<OpeningMargin> margins, const FaceTemplateInfo& info) {
  if (!info.eyelid_rim && !info.lip_rim) return margins;
  std::vector<std::uint32_t> rims = info.eyelid_rim.value_or(std::vector<std::uint32_t>{});
  if (info.lip_rim) rims.insert(rims.end(), info.lip_rim->begin(), info.lip_rim->end());
  std::sort(rims.begin(), rims.end());
  std::erase_if(margins, [&](const OpeningMargin& margin) {
    return !std::binary_search(rims.begin(), rims.end(), margin.vertex);
  });
  return margins;
}

}  // namespace

struct TemplatePreparation::State {
  OpeningParams openings;
  bool synthesise_tongue_out = true;
  bool align_margins = true;

  std::once_flag given_once, synthesised_once;
  PreparedTemplate given;
  std::optional<Rig> with_tongue_out;
  std::optional<PreparedTemplate> synthesised;  // nullopt once tried: none could be made

  PreparedTemplate Prepare(const Rig& rig, const FaceTemplateInfo& info, std::string tongue_part) const {
    PreparedTemplate prepared;
    prepared.rig = &rig;
    prepared.tongue_out_synthesised_from = std::move(tongue_part);
    if (align_margins) prepared.margins = DescribedMargins(FindOpeningMargins(rig, openings), info);
    return prepared;
  }
};

TemplatePreparation::TemplatePreparation(const Rig& template_rig, const FaceTemplateInfo& info,
                                         const BuildRigParams& params)
    : template_rig_(&template_rig), info_(&info), state_(std::make_unique<State>()) {
  if (template_rig.shape_count() == 0) {
    throw InvalidInputError("the template has no blend shapes to transfer");
  }
  if (info.region.last >= template_rig.vertex_count()) {
    throw InvalidInputError("the template descriptor's region ends at vertex " + std::to_string(info.region.last) +
                            ", the template has " + std::to_string(template_rig.vertex_count()) + " vertices");
  }
  state_->openings = params.openings;
  state_->synthesise_tongue_out = params.synthesise_tongue_out;
  state_->align_margins = params.align_margins_to_openings;
}

TemplatePreparation::~TemplatePreparation() = default;
TemplatePreparation::TemplatePreparation(TemplatePreparation&&) noexcept = default;
TemplatePreparation& TemplatePreparation::operator=(TemplatePreparation&&) noexcept = default;

const PreparedTemplate& TemplatePreparation::For(const RawRig& target) const {
  // A target with a tongueOut of its own keeps it (the built-in head moves its own tongue better
  // than ICT's mapped onto it).
  const std::string wanted = CanonicalShapeNameOf("tongueOut").full();
  return For(std::any_of(target.shapes.begin(), target.shapes.end(), [&](const RawBlendShape& shape) {
    return CanonicalShapeNameOf(shape.name).full() == wanted;
  }));
}

const PreparedTemplate& TemplatePreparation::For(bool target_has_tongue_out) const {
  State& state = *state_;
  if (state.synthesise_tongue_out && !target_has_tongue_out) {
    std::call_once(state.synthesised_once, [&] {
      SynthesisedTongueOut tongue_out;
      state.with_tongue_out = WithSynthesisedTongueOut(*template_rig_, *info_, &tongue_out);
      if (state.with_tongue_out) state.synthesised = state.Prepare(*state.with_tongue_out, *info_, tongue_out.part);
    });
    if (state.synthesised) return *state.synthesised;
  }
  std::call_once(state.given_once, [&] { state.given = state.Prepare(*template_rig_, *info_, {}); });
  return state.given;
}

}  // namespace facerig
