// Coarticulation: a time-sorted track of viseme keys -> per-frame viseme
// weights, by dominance blending (Cohen & Massaro 1993) followed by a contact
// pass that guarantees lip closure for p/b/m and lip-teeth contact for f/v.
//
// Blending. Each key i (viseme v_i, strength S_i) has a dominance
//   D_i(t) = alpha_v * exp(-theta_v * tau^c_v),
//   tau    = max(0, |t - centre_i| - hold_fraction * duration_i / 2)   (seconds)
// with theta = anticipatory rate before the centre and carry-over rate after
// it. Long keys thus hold their full dominance over their central part; short
// keys peak at their centre. The blended weights are
//   w_v(t) = articulation_strength * sum_{i: v_i = v} D_i(t) S_i / (rest + sum_i D_i(t)),
// clamped to [0,1]. `rest` is a small constant dominance of the rest pose, so
// the mouth relaxes (all weights -> 0) far from any key.
//
// Contact pass (the hard constraint). Dominance blending alone averages a
// 30 ms "p" between two open vowels into a half-closed mouth. So every PP and
// FF key also has a contact envelope E(t) in [0,1]: 1 over a hold around the
// key's centre (at least `contact_min_hold` either side, so a 60 fps frame
// always lands in it), falling to 0 with a smoothstep over
// `contact_anticipation` before and `contact_release` after. The envelopes
// override the blend: with A_v = 1 - prod_{keys of v} (1 - E_i) for v in
// {PP, FF} and the total contact K = 1 - (1 - A_PP)(1 - A_FF),
//   every w_u <- (1 - K) w_u,   then w_PP += K s,  w_FF += K (1 - s),
//   s = A_PP (1 - A_FF) / (A_PP (1 - A_FF) + A_FF (1 - A_PP)).
// For a lone contact key this is w_c <- E + (1 - E) w_c, others (1 - E) w_u.
// Where a key is in its hold (E = 1) its viseme's weight is exactly 1 and every
// other viseme (all of which open the lips) exactly 0, whatever the
// neighbours, the key strength or the articulation strength; the pass is
// continuous in time. (Only if a PP and an FF hold overlap, i.e. their centres
// are closer than their holds, does the nearer centre take all.)
//
// Jaw and lip intensities (JALI) act on rig weights, where the jaw- and
// lip-driven shapes are known: see VisemeWeightsJob (viseme_mapping.h).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "facerig/runtime/speech/viseme.h"
#include "facerig/runtime/speech/viseme_track.h"

namespace facerig {

// One weight per viseme, indexed by static_cast<std::size_t>(Viseme), in [0,1].
using VisemeWeights = std::array<float, kVisemeCount>;

// Cohen & Massaro's dominance parameters for one viseme.
struct DominanceParams {
  float magnitude = 1.0f;          // alpha in (0,1]: how strongly the viseme claims the mouth
  float anticipatory_rate = 60.0f; // theta before the key's centre, in s^-c; smaller = reaches further ahead
  float carryover_rate = 60.0f;    // theta after the key's centre, in s^-c
  float exponent = 1.5f;           // c > 0; c > 1 makes D flat (C1) at the hold edge
};

using DominanceTable = std::array<DominanceParams, kVisemeCount>;

// The built-in table, indexed by Viseme; coarticulation.cpp says where the
// values come from.
const DominanceTable& DefaultDominanceTable();

struct CoarticulationParams {
  const DominanceTable* table = &DefaultDominanceTable();
  // Scales every blended weight: < 1 under-articulated (mumbled), > 1
  // exaggerated (weights still clamped to [0,1]). The contact pass is applied
  // after it, so p/b/m and f/v stay complete. Range [0, 4].
  float articulation_strength = 1.0f;
  // Share of a key's duration (centred) over which its dominance stays at alpha. [0,1].
  float hold_fraction = 0.5f;
  // Dominance of the rest pose; > 0.
  float rest_dominance = 1e-3f;

  // Contact envelope of PP and FF keys (seconds). Hold half-width is
  // max(contact_min_hold, contact_hold_fraction * duration / 2).
  // 10 ms > half a 60 fps frame: any key at least one frame long contains a
  // sampled frame with full contact (and a sampled frame lies within 10 ms of
  // every shorter key's centre).
  double contact_min_hold = 0.010;
  float contact_hold_fraction = 0.6f;
  // The lips start closing before the sound (anticipation) and open after
  // it; ~80 ms is the fastest a lip closure from an open vowel looks natural.
  double contact_anticipation = 0.080;
  double contact_release = 0.060;

  // Keys whose interval is farther than this from the evaluated time are
  // ignored. Must cover the contact envelope (min hold + ramps). With the
  // default table a key 0.5 s away has dominance < 1e-5.
  double window = 0.5;

  // True when every value is finite and within its stated range.
  bool Valid() const;
};

enum class CoarticulationError : std::uint8_t {
  kNone,
  kNoParams,
  kInvalidParams,    // CoarticulationParams::Valid() is false, or a table entry is out of range
  kNoOutput,
  kNonFiniteTime,
  kNoKeys,           // no track (an empty track is fine)
};

const char* ToString(CoarticulationError error);

// Evaluates the viseme weights at one time. Owns no memory; Run() allocates
// nothing, throws nothing and takes no lock. Cost: a binary search plus the
// keys within `params->window` of `time`.
struct CoarticulationJob {
  // Keys checked and sorted when they were appended (starts and ends
  // non-decreasing, so the window is found by binary search). An empty track
  // is valid: the mouth is at rest (all weights 0).
  const VisemeTrack* keys = nullptr;
  Seconds time{0.0};  // on the keys' clock
  const CoarticulationParams* params = nullptr;
  VisemeWeights* out_weights = nullptr;

  // Checks the inputs without touching the output: O(1) (the params'
  // fixed-size table, never the keys).
  CoarticulationError Validate() const;
  // Validates, then evaluates. On error the output is left untouched.
  CoarticulationError Run() const;
};

// How strongly the speech holds the lips in contact (p/b/m closure or f/v
// lip-to-teeth) in [0,1]: what other layers (emotions) must not undo.
inline float LipContactWeight(const VisemeWeights& weights) {
  const float sum = weights[static_cast<std::size_t>(Viseme::kPP)] +
                    weights[static_cast<std::size_t>(Viseme::kFF)];
  return sum < 0.0f ? 0.0f : (sum > 1.0f ? 1.0f : sum);
}

}  // namespace facerig
