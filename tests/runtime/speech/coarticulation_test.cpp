#include "facerig/runtime/speech/coarticulation.h"

#include <cmath>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>

#include "measure/allocation_counter.h"
#include "support/test_meshes.h"

namespace facerig {
using test::Key;

namespace {

constexpr std::size_t Index(Viseme v) { return static_cast<std::size_t>(v); }

VisemeTrack Track(std::span<const VisemeKey> keys) {
  VisemeTrack track;
  REQUIRE(VisemeTrack::Make(keys, track) == VisemeTrackError::kNone);
  return track;
}

VisemeWeights Evaluate(std::span<const VisemeKey> keys, double time, const CoarticulationParams& params) {
  VisemeWeights out{};
  const VisemeTrack track = Track(keys);
  CoarticulationJob job{&track, facerig::Seconds(time), &params, &out};
  REQUIRE(job.Run() == CoarticulationError::kNone);
  return out;
}

// True when `target` is exactly 1 and every other viseme exactly 0.
bool FullContact(const VisemeWeights& w, Viseme target) {
  for (std::size_t v = 0; v < facerig::kVisemeCount; ++v) {
    if (w[v] != (v == Index(target) ? 1.0f : 0.0f)) return false;
  }
  return true;
}

// "a <contact> a": open vowels of `vowel_duration` around a short contact key.
std::vector<VisemeKey> Sandwich(Viseme vowel, Viseme contact, double start, double duration,
                                float strength = 1.0f, double vowel_duration = 0.2) {
  return {Key(start - vowel_duration, start, vowel, 1.0f),
          Key(start, start + duration, contact, strength),
          Key(start + duration, start + duration + vowel_duration, vowel, 1.0f)};
}

}  // namespace

TEST_CASE("Coarticulation defaults are valid and the window hides only negligible dominance",
          "[coarticulation]") {
  const CoarticulationParams params;
  REQUIRE(params.Valid());
  // A key whose interval ends `window` before the evaluated time has tau >= window.
  for (const facerig::DominanceParams& d : *params.table) {
    const double rate = std::min(d.anticipatory_rate, d.carryover_rate);
    const double dominance = d.magnitude * std::exp(-rate * std::pow(params.window, d.exponent));
    REQUIRE(dominance < 1e-5);
    // Lip-visible visemes anticipate at least as much as they carry over.
    REQUIRE(d.anticipatory_rate <= d.carryover_rate);
  }
  const auto& pp = (*params.table)[Index(Viseme::kPP)];
  REQUIRE(pp.anticipatory_rate < pp.carryover_rate);
}

TEST_CASE("Coarticulation: a lone vowel peaks at its centre and the mouth rests far away",
          "[coarticulation]") {
  const CoarticulationParams params;
  const std::vector<VisemeKey> keys = {Key(1.0, 1.2, Viseme::kAA, 1.0f)};
  const VisemeWeights centre = Evaluate(keys, 1.1, params);
  REQUIRE(centre[Index(Viseme::kAA)] > 0.99f);
  const VisemeWeights far = Evaluate(keys, 3.0, params);
  for (float w : far) REQUIRE(w == 0.0f);
  const VisemeWeights before = Evaluate(keys, 0.0, params);
  for (float w : before) REQUIRE(w == 0.0f);

  // Key strength scales the target.
  const std::vector<VisemeKey> weak = {Key(1.0, 1.2, Viseme::kAA, 0.5f)};
  REQUIRE(Evaluate(weak, 1.1, params)[Index(Viseme::kAA)] == Approx(0.5f).margin(0.01));
  // Articulation strength scales every weight.
  CoarticulationParams mumbled = params;
  mumbled.articulation_strength = 0.5f;
  REQUIRE(Evaluate(keys, 1.1, mumbled)[Index(Viseme::kAA)] == Approx(0.5f).margin(0.01));
}

TEST_CASE("Coarticulation anticipates: lips round before the sound more than they stay after",
          "[coarticulation]") {
  const CoarticulationParams params;
  const std::vector<VisemeKey> keys = {Key(0.0, 0.3, Viseme::kSil, 1.0f),
                                       Key(0.3, 0.4, Viseme::kOU, 1.0f),
                                       Key(0.4, 0.7, Viseme::kSil, 1.0f)};
  const double lead = 0.06;
  const float before = Evaluate(keys, 0.3 - lead, params)[Index(Viseme::kOU)];
  const float after = Evaluate(keys, 0.4 + lead, params)[Index(Viseme::kOU)];
  REQUIRE(before > 0.05f);
  REQUIRE(before > 1.5f * after);
  // Neighbours blend: a tongue consonant between rounded vowels takes their shape.
  const std::vector<VisemeKey> coo = {Key(0.0, 0.1, Viseme::kKK, 1.0f), Key(0.1, 0.3, Viseme::kOU, 1.0f)};
  REQUIRE(Evaluate(coo, 0.05, params)[Index(Viseme::kOU)] > 0.1f);
}

TEST_CASE("Coarticulation: every short PP and FF between open vowels reaches full contact",
          "[coarticulation]") {
  // Exhaustive over durations (0 to 100 ms), phases against the 60 fps frame
  // grid, neighbouring vowels, key strengths and articulation strengths.
  const double frame = 1.0 / 60.0;
  int cases = 0;
  for (Viseme contact : {Viseme::kPP, Viseme::kFF}) {
    for (Viseme vowel : {Viseme::kAA, Viseme::kOH, Viseme::kE}) {
      for (double duration : {0.0, 0.005, 0.01, 0.015, 0.02, 0.025, 0.03, 0.035, 0.04, 0.06, 0.1}) {
        for (float strength : {1.0f, 0.2f}) {
          for (float articulation : {1.0f, 0.0f, 0.5f, 2.0f, 4.0f}) {
            CoarticulationParams params;
            params.articulation_strength = articulation;
            for (int phase_ms = 0; phase_ms < 17; ++phase_ms) {
              const double start = 1.0 + phase_ms * 0.001;
              const std::vector<VisemeKey> keys = Sandwich(vowel, contact, start, duration, strength);
              const double centre = start + 0.5 * duration;
              INFO("viseme " << facerig::ToString(contact) << " between " << facerig::ToString(vowel)
                             << ", duration " << duration << " s, start " << start << ", strength "
                             << strength << ", articulation " << articulation);
              REQUIRE(FullContact(Evaluate(keys, centre, params), contact));
              // At 60 fps: some sampled frame inside the interval has full
              // contact; a key shorter than a frame gets it at the frame
              // nearest its centre (at most half a frame away).
              bool reached = false;
              for (int f = static_cast<int>(std::floor((start - 0.05) / frame));
                   f * frame <= start + duration + 0.05; ++f) {
                const double t = f * frame;
                const bool sampled = duration >= frame ? (t >= start && t <= start + duration)
                                                       : std::abs(t - centre) <= 0.5 * frame + 1e-12;
                if (sampled && FullContact(Evaluate(keys, t, params), contact)) reached = true;
              }
              REQUIRE(reached);
              ++cases;
            }
          }
        }
      }
    }
  }
  REQUIRE(cases == 2 * 3 * 11 * 2 * 5 * 17);
}

TEST_CASE("Coarticulation: adjacent PP and FF each reach full contact at their centre",
          "[coarticulation]") {
  const CoarticulationParams params;
  for (double d : {0.0, 0.01, 0.02, 0.03, 0.05}) {
    // "a m f a" ("comfort") with two short contacts back to back.
    const std::vector<VisemeKey> keys = {Key(0.8, 1.0, Viseme::kAA, 1.0f),
                                         Key(1.0, 1.0 + d, Viseme::kPP, 1.0f),
                                         Key(1.0 + d, 1.0 + 2 * d, Viseme::kFF, 1.0f),
                                         Key(1.0 + 2 * d, 1.2 + 2 * d, Viseme::kAA, 1.0f)};
    if (d == 0.0) continue;  // two zero-length keys at one instant: only one can win
    INFO("duration " << d);
    REQUIRE(FullContact(Evaluate(keys, 1.0 + 0.5 * d, params), Viseme::kPP));
    REQUIRE(FullContact(Evaluate(keys, 1.0 + 1.5 * d, params), Viseme::kFF));
  }
}

TEST_CASE("Coarticulation output is bounded and continuous over a sentence", "[coarticulation]") {
  const CoarticulationParams params;
  const Viseme seq[] = {Viseme::kSil, Viseme::kDD, Viseme::kE, Viseme::kNN, Viseme::kPP, Viseme::kAA,
                        Viseme::kFF,  Viseme::kOU, Viseme::kSS, Viseme::kIH, Viseme::kKK, Viseme::kOH,
                        Viseme::kRR,  Viseme::kCH, Viseme::kTH, Viseme::kAA, Viseme::kPP, Viseme::kSil};
  std::vector<VisemeKey> keys;
  double t = 0.0;
  for (std::size_t i = 0; i < std::size(seq); ++i) {
    const double d = 0.03 + 0.02 * static_cast<double>(i % 5);
    keys.push_back(Key(t, t + d, seq[i], 1.0f));
    t += d;
  }
  VisemeWeights previous = Evaluate(keys, -0.1, params);
  float largest_step = 0.0f;
  for (double time = -0.1; time < t + 0.2; time += 0.001) {
    const VisemeWeights w = Evaluate(keys, time, params);
    for (std::size_t v = 0; v < facerig::kVisemeCount; ++v) {
      REQUIRE(std::isfinite(w[v]));
      REQUIRE(w[v] >= 0.0f);
      REQUIRE(w[v] <= 1.0f);
      largest_step = std::max(largest_step, std::abs(w[v] - previous[v]));
    }
    previous = w;
  }
  // No jumps: at most 10% of full weight per millisecond.
  REQUIRE(largest_step < 0.1f);

  // The window changes nothing visible.
  CoarticulationParams wide = params;
  wide.window = 5.0;
  for (double time = 0.0; time < t; time += 0.0137) {
    const VisemeWeights a = Evaluate(keys, time, params);
    const VisemeWeights b = Evaluate(keys, time, wide);
    for (std::size_t v = 0; v < facerig::kVisemeCount; ++v) REQUIRE(a[v] == Approx(b[v]).margin(1e-4));
  }
}

TEST_CASE("CoarticulationJob::Run does not allocate", "[coarticulation]") {
  const CoarticulationParams params;
  std::vector<VisemeKey> keys;
  for (int i = 0; i < 400; ++i) {
    const Viseme v = static_cast<Viseme>(i % static_cast<int>(facerig::kVisemeCount));
    keys.push_back(Key(i * 0.07, i * 0.07 + 0.07, v, 1.0f));
  }
  VisemeWeights out{};
  const VisemeTrack track = Track(keys);
  CoarticulationJob job{&track, facerig::Seconds(0.0), &params, &out};
  facerig::test::AllocationCounter counter;
  for (int frame = 0; frame < 600; ++frame) {
    job.time = facerig::Seconds(frame / 60.0);
    REQUIRE(job.Run() == CoarticulationError::kNone);
  }
  REQUIRE(counter.count() == 0);
}

TEST_CASE("CoarticulationJob invalid inputs", "[coarticulation]") {
  const CoarticulationParams params;
  const VisemeTrack keys =
      Track(std::vector<VisemeKey>{Key(0.0, 0.1, Viseme::kAA, 1.0f), Key(0.1, 0.2, Viseme::kPP, 1.0f)});
  VisemeWeights out;
  out.fill(7.0f);
  const VisemeWeights untouched = out;
  auto run = [&](const VisemeTrack* k, double time, const CoarticulationParams* p, VisemeWeights* o) {
    return CoarticulationJob{k, facerig::Seconds(time), p, o}.Run();
  };

  REQUIRE(run(&keys, std::numeric_limits<double>::quiet_NaN(), &params, &out) ==
          CoarticulationError::kNonFiniteTime);
  REQUIRE(run(&keys, std::numeric_limits<double>::infinity(), &params, &out) ==
          CoarticulationError::kNonFiniteTime);
  REQUIRE(run(&keys, 0.1, nullptr, &out) == CoarticulationError::kNoParams);
  REQUIRE(run(&keys, 0.1, &params, nullptr) == CoarticulationError::kNoOutput);

  CoarticulationParams bad = params;
  bad.rest_dominance = 0.0f;
  REQUIRE(run(&keys, 0.1, &bad, &out) == CoarticulationError::kInvalidParams);
  bad = params;
  bad.window = 0.05;  // shorter than the contact envelope
  REQUIRE(run(&keys, 0.1, &bad, &out) == CoarticulationError::kInvalidParams);
  bad = params;
  bad.articulation_strength = std::numeric_limits<float>::quiet_NaN();
  REQUIRE(run(&keys, 0.1, &bad, &out) == CoarticulationError::kInvalidParams);
  bad = params;
  bad.table = nullptr;
  REQUIRE(run(&keys, 0.1, &bad, &out) == CoarticulationError::kInvalidParams);
  facerig::DominanceTable table = facerig::DefaultDominanceTable();
  table[3].anticipatory_rate = -1.0f;
  bad = params;
  bad.table = &table;
  REQUIRE(run(&keys, 0.1, &bad, &out) == CoarticulationError::kInvalidParams);

  REQUIRE(run(nullptr, 0.1, &params, &out) == CoarticulationError::kNoKeys);
  REQUIRE(out == untouched);

  // No keys is not an error: the mouth rests (a character between lines).
  const VisemeTrack empty;
  REQUIRE(run(&empty, 0.1, &params, &out) == CoarticulationError::kNone);
  for (float w : out) REQUIRE(w == 0.0f);
}

}  // namespace facerig
