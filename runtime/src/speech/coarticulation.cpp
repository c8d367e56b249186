#include "facerig/runtime/speech/coarticulation.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace facerig {
namespace {

// The dominance table: Cohen & Massaro's functional form (1993), our numbers.
// They are hand-set, not fitted to measured articulation, following three rules:
// - Lip-visible visemes (PP FF CH RR oh ou) anticipate: their anticipatory rate
//   is lower than their carry-over rate, so dominance reaches further before
//   the sound than after it (lip rounding starts several segments early;
//   Benguerel & Cowan 1974). Tongue consonants are roughly symmetric.
// - Tongue-only consonants (DD kk nn) have low magnitude: the lips and jaw
//   take the shape of the neighbouring vowels ("k" in "key" vs "coo"), which is
//   the coarticulation the model exists for. Contact and fricative visemes
//   (PP FF TH SS CH) and vowels have high magnitude.
// - With c = 1.5, tau is in seconds; a rate of 45 / 90 / 130 halves the
//   dominance 62 / 39 / 31 ms beyond the key's hold, so a typical 60-100 ms
//   segment reaches its neighbours but not the whole word.
// Index order is the Viseme enum: sil PP FF TH DD kk CH SS nn RR aa E ih oh ou.
constexpr DominanceTable kDefaultTable = {{
    //  alpha  theta_ant  theta_carry  c
    {0.60f, 60.0f, 60.0f, 1.5f},     // sil: rest between phrases; mouth relaxes symmetrically
    {1.00f, 50.0f, 90.0f, 1.5f},     // PP: lips close early (contact pass enforces closure)
    {1.00f, 50.0f, 90.0f, 1.5f},     // FF: lower lip to teeth early (contact pass enforces it)
    {0.80f, 80.0f, 110.0f, 1.5f},    // TH
    {0.50f, 110.0f, 130.0f, 1.5f},   // DD: tongue tip; lips follow the vowels
    {0.40f, 110.0f, 130.0f, 1.5f},   // kk: tongue back; the most vowel-coloured consonant
    {0.90f, 55.0f, 90.0f, 1.5f},     // CH: protruded lips, anticipated
    {0.70f, 90.0f, 110.0f, 1.5f},    // SS: teeth close together, spread lips
    {0.45f, 110.0f, 130.0f, 1.5f},   // nn: tongue tip; lips follow the vowels
    {0.70f, 60.0f, 90.0f, 1.5f},     // RR: rounded in English, anticipated
    {0.90f, 70.0f, 80.0f, 1.5f},     // aa
    {0.85f, 70.0f, 80.0f, 1.5f},     // E
    {0.85f, 70.0f, 80.0f, 1.5f},     // ih
    {0.90f, 50.0f, 80.0f, 1.5f},     // oh: rounded, anticipated
    {0.95f, 45.0f, 75.0f, 1.5f},     // ou: strongest rounding anticipation
}};

bool IsContact(Viseme v) { return v == Viseme::kPP || v == Viseme::kFF; }

// tau^c, with the common exponents computed without pow().
double PowExponent(double tau, float c) {
  if (c == 1.0f) return tau;
  if (c == 1.5f) return tau * std::sqrt(tau);
  if (c == 2.0f) return tau * tau;
  return std::pow(tau, static_cast<double>(c));
}

// 1 on the hold, smoothstep down to 0 over the ramp on each side.
double ContactEnvelope(double offset, double half_duration, const CoarticulationParams& params) {
  const double hold = std::max(params.contact_min_hold,
                               static_cast<double>(params.contact_hold_fraction) * half_duration);
  const double outside = std::abs(offset) - hold;
  if (outside <= 0.0) return 1.0;
  const double ramp = offset < 0.0 ? params.contact_anticipation : params.contact_release;
  const double x = outside / ramp;
  if (x >= 1.0) return 0.0;
  return 1.0 - x * x * (3.0 - 2.0 * x);
}

bool Finite(double x) { return std::isfinite(x); }

}  // namespace

const DominanceTable& DefaultDominanceTable() { return kDefaultTable; }

bool CoarticulationParams::Valid() const {
  if (table == nullptr) return false;
  for (const DominanceParams& p : *table) {
    if (!(p.magnitude > 0.0f && p.magnitude <= 1.0f)) return false;
    if (!(p.anticipatory_rate > 0.0f && std::isfinite(p.anticipatory_rate))) return false;
    if (!(p.carryover_rate > 0.0f && std::isfinite(p.carryover_rate))) return false;
    if (!(p.exponent > 0.0f && p.exponent <= 4.0f)) return false;
  }
  if (!(articulation_strength >= 0.0f && articulation_strength <= 4.0f)) return false;
  if (!(hold_fraction >= 0.0f && hold_fraction <= 1.0f)) return false;
  if (!(rest_dominance > 0.0f && std::isfinite(rest_dominance))) return false;
  if (!(contact_min_hold >= 0.0 && Finite(contact_min_hold))) return false;
  if (!(contact_hold_fraction >= 0.0f && contact_hold_fraction <= 1.0f)) return false;
  if (!(contact_anticipation > 0.0 && Finite(contact_anticipation))) return false;
  if (!(contact_release > 0.0 && Finite(contact_release))) return false;
  if (!Finite(window)) return false;
  // The window must see every key whose contact envelope can reach `time`.
  return window >= contact_min_hold + std::max(contact_anticipation, contact_release);
}

const char* ToString(CoarticulationError error) {
  switch (error) {
    case CoarticulationError::kNone: return "no error";
    case CoarticulationError::kNoParams: return "no params";
    case CoarticulationError::kInvalidParams: return "coarticulation params out of range";
    case CoarticulationError::kNoOutput: return "no output";
    case CoarticulationError::kNonFiniteTime: return "time is NaN or infinite";
    case CoarticulationError::kNoKeys: return "no viseme track";
  }
  return "unknown error";
}

CoarticulationError CoarticulationJob::Validate() const {
  if (params == nullptr) return CoarticulationError::kNoParams;
  if (!params->Valid()) return CoarticulationError::kInvalidParams;
  if (out_weights == nullptr) return CoarticulationError::kNoOutput;
  if (!Finite(time.count())) return CoarticulationError::kNonFiniteTime;
  if (keys == nullptr) return CoarticulationError::kNoKeys;
  return CoarticulationError::kNone;
}

CoarticulationError CoarticulationJob::Run() const {
  if (const CoarticulationError e = Validate(); e != CoarticulationError::kNone) return e;
  const CoarticulationParams& p = *params;
  const DominanceTable& table = *p.table;

  // Ends are non-decreasing, so the keys that end at or after (time - window)
  // form a suffix; walk it until keys start after (time + window).
  const Seconds window_start = time - Seconds(p.window);
  const Seconds window_end = time + Seconds(p.window);
  const std::span<const VisemeKey> track = keys->keys();
  const auto first = std::partition_point(track.begin(), track.end(),
                                          [&](const VisemeKey& k) { return k.end < window_start; });

  std::array<double, kVisemeCount> weighted{};
  double total = static_cast<double>(p.rest_dominance);
  // Per contact viseme (PP, FF): prod (1 - E_i) over its keys, and the
  // nearest centre among keys in their hold (E_i = 1), to break exact ties.
  double open_pp = 1.0, open_ff = 1.0;
  double hold_distance_pp = std::numeric_limits<double>::infinity();
  double hold_distance_ff = std::numeric_limits<double>::infinity();
  for (auto it = first; it != track.end() && it->start <= window_end; ++it) {
    const VisemeKey& key = *it;
    const DominanceParams& d = table[static_cast<std::size_t>(key.viseme)];
    const double half = 0.5 * (key.end - key.start).count();
    const double offset = (time - key.start).count() - half;  // < 0: before the centre
    const double tau = std::max(0.0, std::abs(offset) - static_cast<double>(p.hold_fraction) * half);
    const double rate = offset < 0.0 ? d.anticipatory_rate : d.carryover_rate;
    const double dominance = d.magnitude * std::exp(-rate * PowExponent(tau, d.exponent));
    total += dominance;
    weighted[static_cast<std::size_t>(key.viseme)] += dominance * key.strength;
    if (IsContact(key.viseme)) {
      const double envelope = ContactEnvelope(offset, half, p);
      const bool pp = key.viseme == Viseme::kPP;
      (pp ? open_pp : open_ff) *= 1.0 - envelope;
      if (envelope == 1.0) {
        double& nearest = pp ? hold_distance_pp : hold_distance_ff;
        nearest = std::min(nearest, std::abs(offset));
      }
    }
  }

  VisemeWeights& out = *out_weights;
  const double scale = static_cast<double>(p.articulation_strength) / total;
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    out[v] = static_cast<float>(std::clamp(weighted[v] * scale, 0.0, 1.0));
  }

  // The contact pass. With A_v = 1 - prod_i (1 - E_i) per contact viseme, the
  // total contact is K = 1 - (1 - A_pp)(1 - A_ff); every weight is scaled by
  // 1 - K and K is shared between PP and FF in proportion to
  // A_pp (1 - A_ff) : A_ff (1 - A_pp). This is continuous in time (unlike
  // applying envelopes one after the other, whose order would flip), and a
  // key in its hold (A = 1) gets exactly the whole contact unless the other
  // contact viseme is in its hold too; then the nearer centre wins.
  const double a_pp = 1.0 - open_pp;
  const double a_ff = 1.0 - open_ff;
  const double keep = open_pp * open_ff;  // 1 - K
  if (keep < 1.0) {
    double share_pp = 0.5;
    const double claim_pp = a_pp * open_ff;
    const double claim_ff = a_ff * open_pp;
    if (claim_pp + claim_ff > 0.0) {
      share_pp = claim_pp / (claim_pp + claim_ff);
    } else if (a_pp == 1.0 && a_ff == 1.0) {
      share_pp = hold_distance_pp <= hold_distance_ff ? 1.0 : 0.0;
    }
    const double contact = 1.0 - keep;
    for (std::size_t v = 0; v < kVisemeCount; ++v) out[v] = static_cast<float>(keep * out[v]);
    float& pp = out[static_cast<std::size_t>(Viseme::kPP)];
    float& ff = out[static_cast<std::size_t>(Viseme::kFF)];
    pp = std::min(1.0f, static_cast<float>(pp + contact * share_pp));
    ff = std::min(1.0f, static_cast<float>(ff + contact * (1.0 - share_pp)));
  }
  return CoarticulationError::kNone;
}

}  // namespace facerig
