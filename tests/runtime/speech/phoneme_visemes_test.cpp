#include "facerig/runtime/speech/phoneme_visemes.h"

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "measure/allocation_counter.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

Phoneme Ph(double start, double duration, std::string_view symbol,
           std::string_view language = "en-us", bool word_start = false) {
  return test::MakePhoneme(start, duration, symbol, language, word_start);
}

// A track with back-to-back durations, like espeak-ng gives.
std::vector<Phoneme> Track(std::initializer_list<std::pair<double, std::string_view>> events,
                           double end, std::string_view language = "en-us") {
  std::vector<Phoneme> track;
  for (const auto& [start, symbol] : events) track.push_back(Ph(start, 0.0, symbol, language));
  for (std::size_t i = 0; i < track.size(); ++i) {
    const double next = i + 1 < track.size() ? track[i + 1].start.count() : end;
    track[i].duration = facerig::Seconds(next - track[i].start.count());
  }
  return track;
}

Viseme First(std::string_view language, std::string_view symbol) {
  const auto m = LookupPhonemeVisemes(language, symbol);
  REQUIRE(m.has_value());
  REQUIRE(m->count >= 1);
  return m->visemes[0];
}

TEST_CASE("Lookup: consonants map to the 15-viseme set", "[speech][visemes]") {
  CHECK(First("en-us", "p") == Viseme::kPP);
  CHECK(First("en-us", "b") == Viseme::kPP);
  CHECK(First("en-us", "m") == Viseme::kPP);
  CHECK(First("en-us", "f") == Viseme::kFF);
  CHECK(First("en-us", "v") == Viseme::kFF);
  CHECK(First("en-us", "T") == Viseme::kTH);
  CHECK(First("en-us", "D") == Viseme::kTH);
  CHECK(First("en-us", "t") == Viseme::kDD);
  CHECK(First("en-us", "k") == Viseme::kKK);
  CHECK(First("en-us", "tS") == Viseme::kCH);
  CHECK(First("en-us", "S") == Viseme::kCH);
  CHECK(First("en-us", "s") == Viseme::kSS);
  CHECK(First("en-us", "n") == Viseme::kNN);
  CHECK(First("en-us", "l") == Viseme::kNN);
  CHECK(First("en-us", "r") == Viseme::kRR);
  CHECK(First("en-us", "i:") == Viseme::kIH);
  CHECK(First("en-us", "E") == Viseme::kE);
  CHECK(First("en-us", "A:") == Viseme::kAA);
  CHECK(First("en-us", "O:") == Viseme::kOH);
  CHECK(First("en-us", "u:") == Viseme::kOU);
  // Spanish intervocalic b is bilabial; Dutch v is labiodental.
  CHECK(First("es", "B") == Viseme::kPP);
  CHECK(First("es", "v#") == Viseme::kPP);
  CHECK(First("nl", "v#") == Viseme::kFF);
}

TEST_CASE("Lookup: diphthongs split over two visemes", "[speech][visemes]") {
  struct Case {
    std::string_view symbol;
    Viseme first, second;
  };
  for (const Case& c : {Case{"aI", Viseme::kAA, Viseme::kIH}, Case{"eI", Viseme::kE, Viseme::kIH},
                        Case{"OI", Viseme::kOH, Viseme::kIH}, Case{"aU", Viseme::kAA, Viseme::kOU},
                        Case{"oU", Viseme::kOH, Viseme::kOU}, Case{"e@", Viseme::kE, Viseme::kAA},
                        Case{"i@", Viseme::kIH, Viseme::kAA},
                        Case{"U@", Viseme::kOU, Viseme::kAA}}) {
    INFO(c.symbol);
    const auto m = LookupPhonemeVisemes("en", c.symbol);
    REQUIRE(m.has_value());
    CHECK(m->count == 2);
    CHECK(m->visemes[0] == c.first);
    CHECK(m->visemes[1] == c.second);
    CHECK(m->split > 0.0f);
    CHECK(m->split < 1.0f);
    CHECK(m->has(PhonemeVisemes::kVowel));
  }
  // American English: the centring diphthong ends on r.
  CHECK(LookupPhonemeVisemes("en-us", "e@")->visemes[1] == Viseme::kRR);
}

TEST_CASE("Lookup: pauses, marks, fallbacks and languages", "[speech][visemes]") {
  for (std::string_view pause : {"_", "_:", "_!", "_|", "||", "_::", "_;_"}) {
    INFO(pause);
    const auto m = LookupPhonemeVisemes("fr", pause);
    REQUIRE(m.has_value());
    CHECK(m->count == 1);
    CHECK(m->visemes[0] == Viseme::kSil);
  }
  for (std::string_view mark : {"'", ",", "%", "=", "(en)", "(cmn)", "55", "214", "#X1", "?"}) {
    INFO(mark);
    const auto m = LookupPhonemeVisemes("cmn", mark);
    REQUIRE(m.has_value());
    CHECK(m->count == 0);
  }
  // Stress marks stripped, length and variant marks fall back to the base.
  CHECK(First("en", "'aI") == Viseme::kAA);
  CHECK(First("en", ",i:") == Viseme::kIH);
  CHECK(First("ru", "r;") == Viseme::kRR);
  CHECK(First("de", "o:") == Viseme::kOH);
  CHECK(First("xx", "a:") == Viseme::kAA);  // unknown language: base table
  CHECK(First("EN-US", "3:") == Viseme::kRR);  // case-insensitive language
  CHECK(First("en-gb", "3:") == Viseme::kE);   // subtag fallback to en
  CHECK(First("pt-br", "&~") == Viseme::kAA);
  CHECK_FALSE(LookupPhonemeVisemes("en", "Qxz").has_value());
  CHECK(LookupPhonemeVisemes("en", "")->count == 0);  // nothing to articulate
  // Single digits are vowels, not tones.
  CHECK(First("en", "0") == Viseme::kOH);
  CHECK(First("en", "3") == Viseme::kAA);
}

TEST_CASE("Lookup: the espeak-ng inventories of the 14 voices are mapped", "[speech][visemes]") {
  // Phoneme names espeak-ng 1.51 defines for these languages (phontab), plus
  // the base tables they include.
  const std::vector<std::pair<std::string_view, std::vector<std::string_view>>> inventories = {
      {"en-us", {"@", "?", "t#", "a", "i", "r/", "t", "t2", "3", "I2", "@2", "U", "a#", "aa", "A:",
                 "E", "I", "I#", "I2#", "0", "02", "O2", "V", "A@", "A#", "3:", "i:", "O:", "O",
                 "O@", "o@", "u:", "aU", "oU", "aI", "eI", "OI", "e@", "i@", "i@3", "U@", "aI@",
                 "aI3", "aU@"}},
      {"en", {"@", "t#", "r-", "n", "l", "t2", "d#", "z#", "z/2", "w#", "@5", "@L", "a2", "E#",
              "E2", "0#", "oU#", "IR", "VR", "o:", "A~", "O~", "e:", "e#", "a#2", "@#"}},
      {"pt", {"*", "e", "u", "r-", "l", "x", "E", "O", "U", "y", "eU", "aI", "eI", "I", "e~", "i~",
              "o~", "u~", "&~", "&U~", "oI~", "&", "&/", "A", "i/", "OI", "EU", "s#", "R", "w"}},
      {"es", {"r", "a", "e", "b", "d", "g", "v#", "D", "s", "a/", "E", "oI", "e/", "o/", "**",
              "B", "Q", "T", "R2", "N", "n^", "l^", "j", "w", "x"}},
      {"fr", {"@", "@-", "r", "r/", "n", "l", "l/", "w", "l/2", "#l", "#r", "#cFR", "y", "E",
              "A~", "E~", "W~", "O~", "W", "j/", "r/2", "r2", "a-", "a#", "e-", "E-", "I", "I2",
              "O", "oU", "u:", "y-", "W2", "Y", "w/", "n2", "p2", "t2", "t3", "V", "z2", "z3",
              "j.", "Z", "S", "n^"}},
      {"de", {"@", "r", "l/", "j", "x", "3", "E", "E2", "I", "I:", "O", "U", "UR", "A:", "A",
              "i:", "i2", "u:", "aU", "aI", "EI", "OY", "E:", "e:", "o:", "y:", "y", "Y:", "W",
              "ts", "pF", "g#", "iR", "oU", "A~", "W~", "l2", "O~", "C", "N", "?"}},
      {"it", {"l^", "v", "z", "a/", "E", "O", "U", "aU", "aI", "oI", "ts", "o/", "e/", "I", "i/",
              "i#", "ts2", "dz", "ss", "k~", "tS~", "dZ~", "g~", "Q~", "S~", "n^", "tS", "dZ"}},
      {"fi", {":", "R2", "h", "I", "&", "a2", "Y", "u1", "U", "y", "ai", "&i", "oi", "ei", "Yi",
              "ui", "yi", "au", "ou", "eu", "iu", "&y", "ey", "Yy", "iy", "uo", "ie", "yY", "s2"}},
      {"nl", {"Q", "x", "I", "y", "8", "E", "E2", "O", "O:", "a:", "A", "A~", "O~", "e:", "e#",
              "Y:", "o:", "EI", "Wy", "VU", "eU", "yU", "!", "v#"}},
      {"pl", {"R", "w", "a#", "E", "E#", "O", "y", "E~", "O~", "t;", "d;", "ts", "dz", "ts;",
              "dz;", "S;", "Z;", "s;", "z;", "x", "n^"}},
      {"ru", {"l^", "dZ;", "tS;", "s;", "x", "n_", "n#", "ts", "t;", "d;", "m;", "I^", "y", "I#",
              "I", "I2", "I3", "ja", "E", "E#", "E2", "E3", "E%", "V", "O", "8", "u#", "u\"", "ju",
              "ja#", "V#", "A", "Y", "a#", "R4", "r;", "l;", "p;", "b;", "v;", "f;", "k;", "g;"}},
      {"hi", {"@", "t#", "J", "c", "H", "V", "@3", "@2", "i:", "I", "e:", "E:", "E", "&:", "a:",
              "o:", "O:", "O", "U", "u:", "i~", "I~", "e~", "E~", "a~", "V~", "O~", "o~", "U~",
              "u~", "aI", "aU", "p#", "b#", "d#", "t.", "d.", "t.#", "d.#", "c#", "J#", "k#", "g#",
              "#X2", "r.", "s.", "n."}},
      {"cmn", {"@", "N-", "l", "j", "N", "tS;", "f", "s.", "S;", "11", "21", "214", "22", "33",
               "35", "44", "51", "53", "55", "ph", "th", "kh", "tS;h", "ts", "tsh", "ts.", "ts.h",
               "A", "ai", "Au", "@r", "E", "ei", "i[", "i.", "iA", "iAu", "iE", "io", "iou", "o-",
               "ou", "ong", "uA", "ua", "uai", "u@", "uei", "uo", "y", "yu", "y&", "yE", "y@",
               "yi", "z."}},
  };
  for (const auto& [language, symbols] : inventories) {
    for (std::string_view symbol : symbols) {
      INFO(language << " " << symbol);
      CHECK(LookupPhonemeVisemes(language, symbol).has_value());
    }
  }
}

TEST_CASE("FindUnmappedSymbols lists each unknown symbol once", "[speech][visemes]") {
  std::vector<Phoneme> track = {Ph(0.0, 0.1, "a"), Ph(0.1, 0.1, "Qxz"), Ph(0.2, 0.1, "p"),
                                Ph(0.3, 0.1, "Qxz"), Ph(0.4, 0.1, "Zq!", "fr")};
  const auto unmapped = FindUnmappedSymbols(track);
  REQUIRE(unmapped.size() == 2);
  CHECK(unmapped[0].symbol == "Qxz");
  CHECK(unmapped[0].language == "en-us");
  CHECK(unmapped[0].count == 2);
  CHECK(unmapped[1].symbol == "Zq!");
  CHECK(FindUnmappedSymbols(std::vector<Phoneme>{Ph(0, 0.1, "aI")}).empty());

  // At runtime an unmapped symbol becomes the neutral fallback, not a crash.
  const auto keys = PhonemesToVisemeKeys(track);
  REQUIRE(keys.size() == 5);
  CHECK(keys[1].viseme == VisemeTimingParams{}.unmapped_viseme);
  CHECK(keys[1].strength == Approx(VisemeTimingParams{}.unmapped_strength));
}

TEST_CASE("Keys: unvoiced stop closure starts before the release event", "[speech][visemes]") {
  // "a pit": a# at 0, p released at 0.110, I at 0.143, t at 0.340, pause at 0.386.
  const auto track = Track({{0.0, "a#"}, {0.110, "p"}, {0.143, "I"}, {0.340, "t"}, {0.386, "_:"}},
                           0.5);
  const VisemeTimingParams params;
  const auto keys = PhonemesToVisemeKeys(track, params);
  REQUIRE(keys.size() == 5);
  CHECK(keys[1].viseme == Viseme::kPP);
  CHECK(keys[1].start.count() == Approx(0.110 - params.stop_closure));
  CHECK(keys[1].end.count() == Approx(0.143));
  CHECK(keys[0].end.count() == Approx(keys[1].start.count()));  // the vowel before gives way
  CHECK(keys[3].viseme == Viseme::kDD);
  CHECK(keys[3].start.count() == Approx(0.340 - params.stop_closure));
  // Voiced b keeps its event time.
  const auto voiced = PhonemesToVisemeKeys(Track({{0.0, "a#"}, {0.110, "b"}, {0.2, "I"}}, 0.3));
  CHECK(voiced[1].start.count() == Approx(0.110));
}

TEST_CASE("Keys: vowels after l r n m w j start earlier", "[speech][visemes]") {
  const VisemeTimingParams params;
  // "lay": l at 0.1, eI at 0.2 -> eI key at 0.16.
  const auto keys = PhonemesToVisemeKeys(Track({{0.0, "_"}, {0.1, "l"}, {0.2, "eI"}}, 0.4), params);
  REQUIRE(keys.size() == 4);
  CHECK(keys[1].viseme == Viseme::kNN);
  CHECK(keys[1].end.count() == Approx(0.2 - params.vowel_lag));
  CHECK(keys[2].viseme == Viseme::kE);
  CHECK(keys[2].start.count() == Approx(0.2 - params.vowel_lag));
  CHECK(keys[3].viseme == Viseme::kIH);
  CHECK(keys[3].end.count() == Approx(0.4));
  // Not after other consonants.
  const auto after_s = PhonemesToVisemeKeys(Track({{0.1, "s"}, {0.2, "eI"}}, 0.4), params);
  CHECK(after_s[1].start.count() == Approx(0.2));
  // Bounded by the previous phoneme's start (+ its minimum duration).
  const auto short_m = PhonemesToVisemeKeys(Track({{0.1, "m"}, {0.12, "a"}}, 0.3), params);
  CHECK(short_m[1].start.count() == Approx(0.12));
  const auto mid_m = PhonemesToVisemeKeys(Track({{0.1, "m"}, {0.15, "a"}}, 0.3), params);
  CHECK(mid_m[1].start.count() == Approx(0.1 + params.min_duration));
  CHECK(mid_m[0].end.count() == Approx(mid_m[1].start.count()));
}

TEST_CASE("Keys: zero-length events get a minimum duration without overlap", "[speech][visemes]") {
  const VisemeTimingParams params;
  // A zero-length event with room after it.
  std::vector<Phoneme> track = {Ph(0.0, 0.0, "d"), Ph(0.1, 0.1, "a")};
  auto keys = PhonemesToVisemeKeys(track, params);
  REQUIRE(keys.size() == 2);
  CHECK(keys[0].end.count() == Approx(params.min_duration));
  // Squeezed: ends where the next key starts.
  track = {Ph(0.0, 0.0, "d"), Ph(0.01, 0.1, "a")};
  keys = PhonemesToVisemeKeys(track, params);
  CHECK(keys[0].end.count() == Approx(0.01));
  // A zero-length last phoneme.
  track = {Ph(0.0, 0.1, "a"), Ph(0.1, 0.0, "_")};
  keys = PhonemesToVisemeKeys(track, params);
  CHECK(keys[1].end.count() == Approx(0.1 + params.min_duration));
  for (const VisemeKey& key : keys) CHECK(key.end.count() >= key.start.count());
}

TEST_CASE("Keys: order, no overlap, marks hold the previous key", "[speech][visemes]") {
  const auto track = Track({{0.0, "_"}, {0.05, "h"}, {0.1, "@"}, {0.15, "l"}, {0.2, "oU"},
                            {0.35, "'"}, {0.36, "w"}, {0.4, "3:"}, {0.5, "l"}, {0.55, "d"},
                            {0.6, "_:"}},
                           0.8);
  const auto keys = PhonemesToVisemeKeys(track);
  REQUIRE(!keys.empty());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    CHECK(keys[i].end.count() >= keys[i].start.count());
    if (i > 0) CHECK(keys[i].start.count() >= keys[i - 1].end.count() - 1e-12);
    CHECK(keys[i].strength >= 0.0f);
    CHECK(keys[i].strength <= 1.0f);
  }
  // The stress mark made no key; oU's second half holds until w's (shifted) start.
  std::size_t ou = 0;
  while (keys[ou].viseme != Viseme::kOU) ++ou;
  CHECK(keys[ou + 1].viseme == Viseme::kOU);  // w
  CHECK(keys[ou].end.count() == Approx(0.36));
}

TEST_CASE("Keys: bad times are repaired, never crash", "[speech][visemes]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Phoneme> track = {Ph(0.2, 0.1, "a"), Ph(0.1, 0.1, "p"),  Ph(nan, 0.1, "i"),
                                Ph(0.4, nan, "t"), Ph(-1.0, -2.0, "u"), Ph(inf, 0.1, "s"),
                                Ph(0.5, inf, "o")};
  const auto keys = PhonemesToVisemeKeys(track);
  REQUIRE(keys.size() == 7);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    INFO(i);
    CHECK(std::isfinite(keys[i].start.count()));
    CHECK(std::isfinite(keys[i].end.count()));
    CHECK(keys[i].end.count() >= keys[i].start.count());
    if (i > 0) CHECK(keys[i].start.count() >= keys[i - 1].end.count() - 1e-12);
  }
  CHECK(PhonemesToVisemeKeys(std::vector<Phoneme>{}).empty());
}

TEST_CASE("VisemeKeyStream: same keys as the batch, no allocation, clean when full",
          "[speech][visemes]") {
  const auto track = Track({{0.0, "_"}, {0.08, "m"}, {0.14, "aI"}, {0.3, "p"}, {0.33, "aU"},
                            {0.5, "(en)"}, {0.5, "n"}, {0.55, "_:"}},
                           0.7);
  const auto batch = PhonemesToVisemeKeys(track);

  std::array<VisemeKey, 64> storage{};
  std::size_t used = 0;
  VisemeKeyStream stream;
  {
    test::AllocationCounter counter;
    for (const Phoneme& phoneme : track) {
      std::span<VisemeKey> rest(storage.data() + used, storage.size() - used);
      // Too small: refused, nothing consumed.
      CHECK_FALSE(stream.Push(phoneme, rest.first(1)).has_value());
      const auto n = stream.Push(phoneme, rest);
      REQUIRE(n.has_value());
      used += *n;
    }
    CHECK_FALSE(stream.Finish(std::span<VisemeKey>()).has_value());
    const auto n = stream.Finish(std::span<VisemeKey>(storage.data() + used, 2));
    REQUIRE(n.has_value());
    used += *n;
    CHECK(counter.count() == 0);
  }
  REQUIRE(used == batch.size());
  for (std::size_t i = 0; i < used; ++i) {
    INFO(i);
    CHECK(storage[i].viseme == batch[i].viseme);
    CHECK(storage[i].start.count() == batch[i].start.count());
    CHECK(storage[i].end.count() == batch[i].end.count());
  }
  // Finish twice: nothing more. Reset starts a new line.
  CHECK(*stream.Finish(storage) == 0);
  stream.Reset();
  CHECK(*stream.Push(Ph(0.0, 0.1, "a"), storage) == 0);
  CHECK(*stream.Finish(storage) == 1);
}

}  // namespace
}  // namespace facerig
