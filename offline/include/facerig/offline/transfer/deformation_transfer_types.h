// What DeformationTransfer (deformation_transfer.h) takes and returns,
// without the solver: for headers that only pass these on (rig_build.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/openings/openings.h"

namespace facerig {

enum class TransferMode : std::uint8_t {
  // Transfer the template's expression gradients S_0 -> S_i onto T_0.
  kClassic = 0,
  // Paper 000 section V.B: transfer the identity gradients S_0 -> T_0 onto
  // S_i. Fewer eyelid artefacts when the target's eyes differ from the template's.
  kIdentityGradient,
};

const char* ToString(TransferMode mode);

struct DeformationTransferParams {
  TransferMode mode = TransferMode::kClassic;
  // Vertices whose position in every expression is fixed to target rest +
  // displacement_scale * template displacement (Pawaskar et al.'s `-cv`). Empty:
  // the template's static set, the vertices that no expression passed to the
  // precomputation moves by more than static_threshold times the source
  // neutral's bounding-box diagonal. Vertices used by no triangle are always anchors.
  // The default 3e-3 (1.4 mm on ICT's 47.5 cm) takes the skin that stays on
  // the skull (scalp, ears, neck, upper forehead). Measured on one random ICT
  // identity, before still pinning (below): median relative error 0.060 at
  // 1e-4 (7.7k anchors), 0.052 at 2e-3, 0.047 at 3e-3 (10.3k), 0.040 at 5e-3;
  // larger values turn into displacement transfer, which is exact only for
  // same-size faces.
  std::vector<std::uint32_t> anchor_vertices;
  float static_threshold = 3e-3f;
  // Connected parts with no anchor (jaw, teeth, eyeballs, which move as a
  // whole in some expressions) get a gauge vertex, and after the solve are
  // translated so that their mean displacement is displacement_scale times the
  // template's mean displacement of that part (exact least-squares optimum:
  // the gradient energy of a free part does not depend on its translation).
  // 1 for a same-size target; e.g. the bounding-box ratio target/template otherwise.
  float displacement_scale = 1.0f;
  // Weight each triangle's gradient residual by its area on the target (the
  // integral of the gradient error) instead of 1 per triangle (Pawaskar et al.).
  bool area_weighted = true;
  // Source frames [e1 e2 n]: false, the unit normal of Pawaskar et al.'s eq. 1;
  // true, Sumner & Popovic's 4th vertex (normal scaled by 1/sqrt(|e1 x e2|),
  // so out-of-plane stretch follows in-plane stretch). The unit normal
  // measured better on ICT identities (median 0.047 vs 0.049, p90 0.075 vs 0.074).
  bool scaled_normal = false;
  // Needle and degenerate triangles: the target's 2x2 edge Gram matrix has its
  // smallest eigenvalue clamped to this fraction of the largest (and to a tiny
  // fraction of the mean squared edge), and source triangles whose frame is
  // this ill-conditioned transfer their edge differences instead of a gradient.
  double min_gram_ratio = 1e-4;
  // Weak displacement prior (0: off, pure deformation transfer): every free
  // vertex is also pulled towards target rest + displacement_scale * template
  // displacement with this weight relative to the system's mean diagonal.
  // It adds a constant diagonal, so the sparsity is unchanged. It blends
  // towards displacement transfer where the gradients leave the position
  // loosely held: on thin features (lids, lip rolls, eyeWide's brow-to-lid
  // skin) the gradient solve rotates the template's deltas with the target's
  // surface and lets small bends add up over the region. On 8 random ICT faces
  // (seed 1, still pinning and contacts on) the classic median / p90 went
  // 0.051 / 0.105 (off), 0.040 / 0.078 (1e-3), 0.033 / 0.063 (3e-3),
  // 0.022 / 0.046 (1e-2); seed 2: 0.071 / 0.111 (off), 0.042 / 0.072 (3e-3).
  // Those truths are additive (ICT's expressions are added to every identity),
  // so a large weight only copies them: 3e-3 is the smallest that meets the
  // issue's 0.05 / 0.08 on both seeds. On the built-in stylized head it also
  // closed the blink a little further (upper to lower lid 0.072 -> 0.061 cm),
  // and it did not add self-intersections on ICT (new skin pairs 3013 -> 2983).
  double displacement_prior = 3e-3;
  // Per expression, the vertices that the template's expression moves by at
  // most still_fraction of its largest displacement are fixed as well (at
  // target rest + displacement_scale * template displacement), and only the
  // rest is solved: what the template leaves still stays still, and the
  // gradient mismatch of the moved region cannot add up, across the whole
  // face, into a rigid offset of that region (0.092 of eyeWide_L's 0.128
  // error with the static anchors alone). Costs one small factorization per
  // expression instead of one shared one. 0: off (the static anchors only).
  double still_fraction = 0.01;
  // With still pinning: in each connected part, the vertices an expression
  // moves are placed as one rigid body when the template moves them as one
  // (RMS residual of their best rigid fit <= rigid_tolerance of their RMS
  // motion): the template's rotation about their centroid on the target and
  // the template's mean displacement (times displacement_scale), then pinned.
  // ICT: the lower gums and tongue in the jaw shapes (residual 0.000-0.021;
  // the skin's is 0.64-0.98). Solved as a gradient field instead, the gums of
  // a random identity ended 0.8 mm off in jawOpen, and the teeth (placed as a
  // whole) went through them: 956 new gums x teeth pairs against the truth's
  // 100. 0: off.
  double rigid_tolerance = 0.05;
  // With still pinning (still_fraction > 0): where the template's expression
  // brings together two vertices of one part that face each other across an
  // opening (the lids on a blink; OpeningParams' contact_* fields are the rule), the
  // transferred expression brings them together (close_contacts, below) or
  // keeps their offset, with this weight relative to the system's mean
  // diagonal. Gradients alone stop a lid short when the target's eye is
  // shaped differently: on ICT with its eyes opened 1.5x taller, eyeBlink
  // left a gap of 12% of the eye width (template 2.1%); 3.2% keeping the
  // offset, 0.8% closing it. 0: off. Without still pinning (still_fraction 0) no
  // contacts are kept whatever this weight: the one factorization shared by
  // all expressions cannot take each expression's own contacts (the
  // result's contacts_active says whether they acted).
  double contact_weight = 10.0;
  // Contacts close completely: the moving vertex goes onto its partner,
  // dropping the offset the template leaves. A blink is meant to close, and
  // ICT-FaceKit's stops short by 2.1% of the eye's width (0.5 mm, under its
  // lashes); a target without lashes shows it. Measured: the worst eye of 8
  // random ICT faces 0.021 -> 0.0075 of the eye width (template 0.021), the
  // built-in stylized head's upper to lower lid 0.056-0.066 -> 0.031-0.040 cm.
  // The cost: where the template's partner lies below the lower margin row,
  // the lid closes onto it, 0.6 mm below that row on ICT with its eyes
  // opened 1.5x (0.4 mm keeping the offset). false: keep the template's
  // offset, times displacement_scale.
  bool close_contacts = true;
  // Which pairs are contacts (contact_* fields; BuildRig sets these from
  // BuildRigParams::openings).
  OpeningParams openings;
  // Worker threads for DeformationTransfer (>= 1).
  int threads = 2;
};

struct DeformationTransferResult {
  std::vector<std::vector<glm::vec3>> expressions;  // per expression, #V target positions
  std::vector<double> residuals;                    // per expression, as SolveDeformationTransfer
  std::size_t anchor_count = 0;
  std::size_t floating_components = 0;
  std::size_t regularized_triangles = 0;
  // Whether contacts acted (DeformationTransferData::contacts_active: false
  // when contact_weight is 0 or still_fraction is 0), and per expression the
  // contact pairs kept (0 where the template's expression closes no opening;
  // all 0 when !contacts_active).
  bool contacts_active = false;
  std::vector<std::size_t> contact_counts;
  double precompute_seconds = 0.0;  // including the factorization
  double factorize_seconds = 0.0;
  double solve_seconds = 0.0;  // all expressions
};

}  // namespace facerig
