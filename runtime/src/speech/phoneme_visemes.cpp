#include "facerig/runtime/speech/phoneme_visemes.h"

#include <algorithm>
#include <cmath>

namespace facerig {
namespace {

using V = Viseme;
using F = PhonemeVisemes;

struct Entry {
  std::string_view symbol;
  PhonemeVisemes map;
};

constexpr PhonemeVisemes Make(V a, V b, std::uint8_t count, float split, float strength,
                              std::uint8_t flags) {
  PhonemeVisemes m;
  m.visemes = {a, b};
  m.count = count;
  m.split = split;
  m.strength = strength;
  m.flags = flags;
  return m;
}

// Table builders: consonant, lag-source consonant (l r n m w j), unvoiced
// stop, vowel, diphthong (two visemes), and "no articulation of its own".
constexpr Entry C(std::string_view s, V v, float strength = 1.0f) {
  return {s, Make(v, v, 1, 0.5f, strength, F::kNone)};
}
constexpr Entry L(std::string_view s, V v, float strength = 1.0f) {
  return {s, Make(v, v, 1, 0.5f, strength, F::kLagSource)};
}
constexpr Entry P(std::string_view s, V v) {
  return {s, Make(v, v, 1, 0.5f, 1.0f, F::kUnvoicedStop)};
}
constexpr Entry Vw(std::string_view s, V v, float strength = 1.0f) {
  return {s, Make(v, v, 1, 0.5f, strength, F::kVowel)};
}
constexpr Entry D(std::string_view s, V a, V b, float split = 0.5f, float strength = 1.0f) {
  return {s, Make(a, b, 2, split, strength, F::kVowel)};
}
constexpr Entry Skip(std::string_view s) { return {s, Make(V::kSil, V::kSil, 0, 0.5f, 0.0f, 0)}; }

// Reduced vowels (schwa and kin) are articulated weakly.
constexpr float kReduced = 0.6f;
// Centring diphthongs (e@, i@, U@) hold their first part longer.
constexpr float kCentring = 0.6f;
// Rising diphthongs with a glide onset (ja, ju, iA, uA) have a short first part.
constexpr float kGlideOnset = 0.35f;

// Shared by every language: espeak-ng's base1/base2 phoneme names, which the
// language tables inherit.
constexpr Entry kBase[] = {
    // Stress, length, syllable and virtual marks: no articulation.
    Skip("'"), Skip(","), Skip("%"), Skip("%%"), Skip(",,"), Skip("''"), Skip("="), Skip(":"),
    Skip("-"), Skip("'!"), Skip("1"), Skip("?"), Skip("!"),
    // Bilabials and labiodentals.
    P("p", V::kPP), C("b", V::kPP), L("m", V::kPP), L("m-", V::kPP), C("B", V::kPP),
    C("f", V::kFF), C("v", V::kFF), C("v#", V::kFF),
    // Dental, alveolar.
    P("t", V::kDD), C("d", V::kDD), P("t[", V::kDD), C("d[", V::kDD), C("t#", V::kDD),
    P("t.", V::kDD), C("d.", V::kDD), P("t;", V::kDD), C("d;", V::kDD),
    C("T", V::kTH), C("D", V::kTH),
    C("s", V::kSS), C("z", V::kSS), P("ts", V::kSS), C("dz", V::kSS),
    // Post-alveolar, retroflex, alveolo-palatal: lips protruded (sh).
    C("S", V::kCH), C("Z", V::kCH), P("tS", V::kCH), C("dZ", V::kCH), P("tS;", V::kCH),
    C("dZ;", V::kCH), C("S;", V::kCH), C("Z;", V::kCH), C("s.", V::kCH), C("z.", V::kCH),
    C("s;", V::kCH), C("z;", V::kCH), P("c", V::kCH), C("J", V::kCH), P("ts;", V::kCH),
    C("dz;", V::kCH),
    // Velar, uvular, palatal, glottal fricatives: tongue body, lips neutral.
    P("k", V::kKK), C("g", V::kKK), P("q", V::kKK), C("x", V::kKK), C("X", V::kKK),
    C("Q", V::kKK), C("Q^", V::kKK), C("Q\"", V::kKK), C("C", V::kKK), C("J^", V::kKK),
    C("h", V::kKK, 0.4f), C("H", V::kKK, 0.4f), L("N", V::kKK), L("N-", V::kKK),
    // Nasals and laterals.
    L("n", V::kNN), L("n-", V::kNN), L("n.", V::kNN), L("n^", V::kNN), L("l", V::kNN),
    L("l-", V::kNN), L("l/", V::kNN), L("l/2", V::kNN), L("l/3", V::kNN), L("l^", V::kNN),
    L("l.", V::kNN), L("L", V::kNN), L("L/", V::kNN), C("l#", V::kNN),
    // Rhotics.
    L("r", V::kRR), L("r-", V::kRR), L("r/", V::kRR), L("r.", V::kRR), L("r\"", V::kRR),
    L("R", V::kRR), L("R2", V::kRR), L("R3", V::kRR), L("**", V::kRR), L("*", V::kRR),
    // Glides; ";" is espeak's palatal glide/palatalisation ("I;@").
    L("j", V::kIH), L("w", V::kOU), L("w2", V::kOU), L(";", V::kIH, 0.5f),
    // Vowels.
    Vw("a", V::kAA), Vw("a/", V::kAA), Vw("A", V::kAA), Vw("&", V::kAA), Vw("V", V::kAA),
    Vw("e", V::kE), Vw("E", V::kE), Vw("3", V::kE, 0.7f),
    Vw("i", V::kIH), Vw("I", V::kIH), Vw("y", V::kOU),
    Vw("o", V::kOH), Vw("O", V::kOH), Vw("0", V::kOH), Vw("8", V::kOH), Vw("Y", V::kOH),
    Vw("W", V::kOH),
    Vw("u", V::kOU), Vw("U", V::kOU),
    Vw("@", V::kAA, kReduced), Vw("@-", V::kAA, 0.5f),
    // base2 diphthongs.
    D("aU", V::kAA, V::kOU), D("eU", V::kE, V::kOU), D("iU", V::kIH, V::kOU),
    D("aI", V::kAA, V::kIH), D("eI", V::kE, V::kIH), D("EI", V::kE, V::kIH),
    D("oI", V::kOH, V::kIH), D("uI", V::kOU, V::kIH), D("OI", V::kOH, V::kIH),
    D("oU", V::kOH, V::kOU), D("EU", V::kE, V::kOU),
};

// English (en = en-gb and the shared en table).
constexpr Entry kEn[] = {
    Vw("3", V::kAA, kReduced), Vw("3:", V::kE), Vw("@2", V::kAA, kReduced),
    Vw("@5", V::kAA, kReduced), Vw("@#", V::kAA, kReduced),
    D("@L", V::kAA, V::kNN, 0.4f, 0.8f),
    Vw("I2", V::kIH, 0.7f), Vw("I2#", V::kIH, 0.7f), Vw("a#", V::kAA, 0.7f),
    Vw("a#2", V::kAA, 0.7f), Vw("a", V::kAA), Vw("aa", V::kAA), Vw("A:", V::kAA),
    Vw("A#", V::kAA), Vw("A@", V::kAA), Vw("O@", V::kOH), Vw("o@", V::kOH), Vw("V", V::kAA),
    Vw("0", V::kOH), Vw("02", V::kOH), Vw("O2", V::kOH), Vw("O:", V::kOH),
    D("aI@", V::kAA, V::kIH), D("aI3", V::kAA, V::kIH), D("aU@", V::kAA, V::kOU),
    D("oU#", V::kOH, V::kOU),
    D("e@", V::kE, V::kAA, kCentring), D("i@", V::kIH, V::kAA, kCentring),
    D("i@3", V::kIH, V::kAA, kCentring), D("U@", V::kOU, V::kAA, kCentring),
    D("IR", V::kIH, V::kRR), D("VR", V::kAA, V::kRR),
    C("t#", V::kDD), P("t2", V::kDD), C("d#", V::kDD), C("z#", V::kSS), C("z/2", V::kSS),
    L("w#", V::kOU),
};

// American English: rhotic vowels end on (or are) an r.
constexpr Entry kEnUs[] = {
    Vw("3", V::kRR, 0.7f), Vw("3:", V::kRR),
    D("A@", V::kAA, V::kRR, kCentring), D("O@", V::kOH, V::kRR, kCentring),
    D("o@", V::kOH, V::kRR, kCentring), D("e@", V::kE, V::kRR, kCentring),
    D("i@3", V::kIH, V::kRR, kCentring), D("U@", V::kOU, V::kRR, kCentring),
    D("aI3", V::kAA, V::kRR), Vw("aa", V::kAA),
};

// Portuguese (pt = pt-pt; pt-br uses the same names).
constexpr Entry kPt[] = {
    L("*", V::kRR), C("R", V::kKK), C("x", V::kKK), Vw("&", V::kAA, 0.8f), Vw("&/", V::kAA, 0.8f),
    Vw("y", V::kIH, 0.7f), Vw("i/", V::kIH), Vw("U", V::kOU, 0.8f), C("s#", V::kCH),
    Vw("e~", V::kE), Vw("i~", V::kIH), Vw("o~", V::kOH), Vw("u~", V::kOU), Vw("&~", V::kAA),
    D("&U~", V::kAA, V::kOU), D("oI~", V::kOH, V::kIH), D("iU", V::kIH, V::kOU),
};

// Spanish: b d g between vowels are approximants (B D Q); "v#" is a bilabial.
constexpr Entry kEs[] = {
    L("r", V::kRR), C("v#", V::kPP), C("D", V::kTH), Vw("e/", V::kE), Vw("o/", V::kOH),
};

// French: schwa and the front rounded vowels are rounded.
constexpr Entry kFr[] = {
    Vw("@", V::kOH, 0.7f), Vw("@-", V::kOH, 0.5f), Vw("y-", V::kOU), Vw("W2", V::kOH),
    Vw("a-", V::kAA), Vw("e-", V::kE), Vw("E-", V::kE), Vw("I2", V::kIH), Vw("u:", V::kOU),
    Vw("A~", V::kAA), Vw("E~", V::kE), Vw("O~", V::kOH), Vw("W~", V::kOH),
    L("w", V::kOU), L("w/", V::kOU), L("j/", V::kIH), L("j.", V::kIH), L("n2", V::kNN),
    P("p2", V::kPP), P("t2", V::kDD), P("t3", V::kDD), C("z2", V::kSS), C("z3", V::kSS),
    L("r2", V::kRR), L("r/2", V::kRR), Skip("#l"), Skip("#r"), Skip("#cFR"),
};

// German.
constexpr Entry kDe[] = {
    Vw("3", V::kAA, kReduced), Vw("I:", V::kIH), Vw("i2", V::kIH), Vw("E2", V::kE),
    Vw("y:", V::kOU), Vw("Y:", V::kOH), Vw("A:", V::kAA),
    D("OY", V::kOH, V::kIH), D("UR", V::kOU, V::kRR), D("iR", V::kIH, V::kRR),
    Vw("A~", V::kAA), Vw("O~", V::kOH), Vw("W~", V::kOH),
    L("l2", V::kNN), C("g#", V::kKK),
    // pf: lips closed, then lower lip to the teeth.
    {"pF", Make(V::kPP, V::kFF, 2, 0.4f, 1.0f, F::kUnvoicedStop)},
};

// Italian: geminates carry a "~".
constexpr Entry kIt[] = {
    Vw("i#", V::kIH), Vw("e/", V::kE), Vw("o/", V::kOH), Vw("i/", V::kIH), P("ts2", V::kSS),
    C("ss", V::kSS), P("k~", V::kKK), P("tS~", V::kCH), C("dZ~", V::kCH), C("g~", V::kKK),
    L("Q~", V::kNN), C("S~", V::kCH),
};

// Finnish: vowel sequences are diphthong phonemes.
constexpr Entry kFi[] = {
    Vw("&", V::kAA), Vw("a2", V::kAA), Vw("u1", V::kOU), C("s2", V::kSS),
    D("ai", V::kAA, V::kIH), D("&i", V::kAA, V::kIH), D("oi", V::kOH, V::kIH),
    D("ei", V::kE, V::kIH), D("Yi", V::kOH, V::kIH), D("ui", V::kOU, V::kIH),
    D("yi", V::kOU, V::kIH), D("au", V::kAA, V::kOU), D("ou", V::kOH, V::kOU),
    D("eu", V::kE, V::kOU), D("iu", V::kIH, V::kOU), D("&y", V::kAA, V::kOU),
    D("ey", V::kE, V::kOU), D("Yy", V::kOH, V::kOU), D("iy", V::kIH, V::kOU),
    D("uo", V::kOU, V::kOH), D("ie", V::kIH, V::kE), D("yY", V::kOU, V::kOH),
};

// Dutch.
constexpr Entry kNl[] = {
    C("v#", V::kFF), Vw("e#", V::kE), Vw("Y:", V::kOH), Vw("O:", V::kOH),
    D("Wy", V::kOH, V::kOU), D("VU", V::kAA, V::kOU), Vw("yU", V::kOU),
};

// Polish: "w" is the letter l (a glide), "y" is a central i.
constexpr Entry kPl[] = {
    Vw("y", V::kIH), Vw("a#", V::kAA), Vw("E#", V::kE), Vw("E~", V::kE), Vw("O~", V::kOH),
};

// Russian: palatalised consonants carry ";", iotated vowels are ja/ju.
constexpr Entry kRu[] = {
    Vw("y", V::kIH), Vw("Y", V::kIH), Vw("I^", V::kIH), Vw("I#", V::kIH), Vw("a#", V::kAA),
    Vw("u#", V::kOU), Vw("u\"", V::kOU), Vw("V#", V::kAA), C("s;", V::kSS), C("z;", V::kSS),
    L("m;", V::kPP), L("n_", V::kNN), L("n#", V::kNN), L("R4", V::kRR),
    D("ja", V::kIH, V::kAA, kGlideOnset), D("ja#", V::kIH, V::kAA, kGlideOnset),
    D("ju", V::kIH, V::kOU, kGlideOnset),
};

// Hindi: "#" marks aspiration, "." retroflex, "~" nasal vowels.
constexpr Entry kHi[] = {
    Vw("@", V::kAA, 0.8f), Vw("&:", V::kAA), Vw("a~", V::kAA), Vw("V~", V::kAA),
    Vw("E~", V::kE), Vw("e~", V::kE), Vw("i~", V::kIH), Vw("I~", V::kIH), Vw("O~", V::kOH),
    Vw("o~", V::kOH), Vw("U~", V::kOU), Vw("u~", V::kOU),
    P("t#", V::kDD), P("p#", V::kPP), C("b#", V::kPP), C("d#", V::kDD), P("t.#", V::kDD),
    C("d.#", V::kDD), P("c#", V::kCH), C("J#", V::kCH), P("k#", V::kKK), C("g#", V::kKK),
    L("r.", V::kRR), C("s.", V::kCH), Skip("#X2"),
};

// Mandarin: aspirated stops "h", apical vowels, multi-part finals (a
// triphthong keeps its nucleus and its end).
constexpr Entry kCmn[] = {
    P("ph", V::kPP), P("th", V::kDD), P("kh", V::kKK), P("tS;h", V::kCH), P("tsh", V::kSS),
    P("ts.", V::kCH), P("ts.h", V::kCH), Vw("i[", V::kIH), Vw("i.", V::kIH), Vw("o-", V::kOH),
    D("ai", V::kAA, V::kIH), D("Au", V::kAA, V::kOU), D("@r", V::kAA, V::kRR),
    D("ei", V::kE, V::kIH), D("iA", V::kIH, V::kAA, kGlideOnset), D("iAu", V::kAA, V::kOU),
    D("iE", V::kIH, V::kE, kGlideOnset), D("io", V::kIH, V::kOH, kGlideOnset),
    D("iou", V::kOH, V::kOU), D("ou", V::kOH, V::kOU), D("ong", V::kOU, V::kKK, 0.6f),
    D("uA", V::kOU, V::kAA, kGlideOnset), D("ua", V::kOU, V::kAA, kGlideOnset),
    D("uai", V::kAA, V::kIH), D("u@", V::kOU, V::kAA, kGlideOnset), D("uei", V::kE, V::kIH),
    D("uo", V::kOU, V::kOH, kGlideOnset), Vw("yu", V::kOU), D("y&", V::kOU, V::kAA),
    D("yE", V::kOU, V::kE), D("y@", V::kOU, V::kAA), D("yi", V::kOU, V::kIH),
};

struct LanguageTable {
  std::string_view language;
  std::span<const Entry> entries;
};

constexpr LanguageTable kLanguages[] = {
    {"en-us", kEnUs}, {"en", kEn}, {"pt", kPt}, {"es", kEs}, {"fr", kFr}, {"de", kDe},
    {"it", kIt},      {"fi", kFi}, {"nl", kNl}, {"pl", kPl}, {"ru", kRu}, {"hi", kHi},
    {"cmn", kCmn},    {"zh", kCmn},
};

const PhonemeVisemes* FindIn(std::span<const Entry> entries, std::string_view symbol) {
  for (const Entry& entry : entries) {
    if (entry.symbol == symbol) return &entry.map;
  }
  return nullptr;
}

std::span<const Entry> TableFor(std::string_view language) {
  for (const LanguageTable& table : kLanguages) {
    if (table.language.size() != language.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < language.size() && same; ++i) {
      char c = language[i];
      if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
      if (c == '_') c = '-';
      same = c == table.language[i];
    }
    if (same) return table.entries;
  }
  return {};
}

const PhonemeVisemes* FindChain(std::string_view language, std::string_view symbol) {
  if (const PhonemeVisemes* m = FindIn(TableFor(language), symbol)) return m;
  const std::size_t dash = language.find_first_of("-_");
  if (dash != std::string_view::npos) {
    if (const PhonemeVisemes* m = FindIn(TableFor(language.substr(0, dash)), symbol)) return m;
  }
  return FindIn(kBase, symbol);
}

bool IsStressMark(char c) { return c == '\'' || c == ',' || c == '%' || c == '='; }

bool IsVariantMark(char c) {
  return c == '#' || c == ';' || c == '.' || c == '~' || c == '-' || c == '/' || c == '"' ||
         c == '^' || c == '[' || c == '_' || (c >= '0' && c <= '9');
}

constexpr PhonemeVisemes kSilence = Make(V::kSil, V::kSil, 1, 0.5f, 1.0f, F::kNone);
constexpr PhonemeVisemes kNoArticulation = Make(V::kSil, V::kSil, 0, 0.5f, 0.0f, F::kNone);

bool IsFinite(double x) { return std::isfinite(x); }

}  // namespace

std::optional<PhonemeVisemes> LookupPhonemeVisemes(std::string_view language,
                                                   std::string_view symbol) {
  // Stress marks around a symbol (track files may carry them).
  while (!symbol.empty() && IsStressMark(symbol.front())) symbol.remove_prefix(1);
  while (!symbol.empty() && IsStressMark(symbol.back())) symbol.remove_suffix(1);
  if (symbol.empty()) return kNoArticulation;  // the symbol was only stress marks
  if (symbol.front() == '_' || symbol == "||") return kSilence;
  // Language switches "(en)" and virtual phonemes "#X1" are not sounds.
  if (symbol.front() == '(' || (symbol.front() == '#' && symbol.size() > 1)) {
    return kNoArticulation;
  }
  // Tones ("55", "214"): pitch, not lips. Single digits are vowels (0 3 8) or looked up.
  if (symbol.size() >= 2 &&
      std::all_of(symbol.begin(), symbol.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return kNoArticulation;
  }
  if (const PhonemeVisemes* m = FindChain(language, symbol)) return *m;
  // Length mark, then variant marks, one at a time from the end.
  std::string_view base = symbol;
  while (base.size() > 1 && (base.back() == ':' || IsVariantMark(base.back()))) {
    base.remove_suffix(1);
    if (const PhonemeVisemes* m = FindChain(language, base)) return *m;
  }
  return std::nullopt;
}

std::vector<UnmappedSymbol> FindUnmappedSymbols(std::span<const Phoneme> phonemes) {
  std::vector<UnmappedSymbol> unmapped;
  for (const Phoneme& phoneme : phonemes) {
    const std::string_view language = phoneme.language.view();
    const std::string_view symbol = phoneme.symbol.view();
    if (LookupPhonemeVisemes(language, symbol)) continue;
    auto it = std::find_if(unmapped.begin(), unmapped.end(), [&](const UnmappedSymbol& u) {
      return u.language == language && u.symbol == symbol;
    });
    if (it == unmapped.end()) {
      unmapped.push_back({std::string(language), std::string(symbol), 1});
    } else {
      ++it->count;
    }
  }
  return unmapped;
}

std::optional<std::size_t> VisemeKeyStream::Push(const Phoneme& phoneme,
                                                 std::span<VisemeKey> out) {
  if (out.size() < kMaxVisemeKeysPerPhoneme) return std::nullopt;

  std::optional<PhonemeVisemes> looked_up =
      LookupPhonemeVisemes(phoneme.language.view(), phoneme.symbol.view());
  PhonemeVisemes map;
  if (looked_up) {
    map = *looked_up;
  } else {
    map = Make(params_.unmapped_viseme, params_.unmapped_viseme, 1, 0.5f,
               params_.unmapped_strength, F::kNone);
  }

  // Repair times so that one bad event cannot derail the whole track.
  double start = phoneme.start.count();
  if (!IsFinite(start) || start < 0.0) start = last_reported_start_;
  start = std::max(start, last_reported_start_);
  double duration = phoneme.duration.count();
  if (!IsFinite(duration) || duration < 0.0) duration = 0.0;
  last_reported_start_ = start;

  if (map.count == 0) {
    // No articulation: the pending key holds through this phoneme.
    if (has_pending_) pending_end_ = std::max(pending_end_, start + duration);
    return std::size_t{0};
  }

  // Anticipation: closure before an unvoiced stop's release, vowel after a
  // late-reported consonant.
  double lead = 0.0;
  if (map.has(F::kUnvoicedStop)) {
    lead = params_.stop_closure;
  } else if (map.has(F::kVowel) && has_pending_ && pending_map_.has(F::kLagSource)) {
    lead = params_.vowel_lag;
  }
  double key_start = start - std::max(lead, 0.0);
  if (has_pending_) {
    // Never before the previous key start, and leave it min_duration if it had it.
    const double keep = std::min(params_.min_duration, start - pending_start_);
    key_start = std::max(key_start, pending_start_ + std::max(keep, 0.0));
  } else {
    key_start = std::max(key_start, 0.0);
  }
  key_start = std::min(key_start, start);

  std::size_t written = 0;
  if (has_pending_) written = EmitPending(key_start, out);

  has_pending_ = true;
  pending_map_ = map;
  pending_start_ = key_start;
  pending_reported_ = start;
  pending_end_ = start + std::max(duration, params_.min_duration);
  return written;
}

std::optional<std::size_t> VisemeKeyStream::Finish(std::span<VisemeKey> out) {
  if (out.size() < kMaxVisemeKeysPerPhoneme) return std::nullopt;
  if (!has_pending_) return std::size_t{0};
  const std::size_t written = EmitPending(pending_end_, out);
  has_pending_ = false;
  return written;
}

void VisemeKeyStream::Reset() {
  has_pending_ = false;
  last_reported_start_ = 0.0;
}

std::size_t VisemeKeyStream::EmitPending(double next_start, std::span<VisemeKey> out) {
  // The pending key ends at its own end (min_duration applied) but never
  // overlaps the next key.
  const double start = pending_start_;
  const double end = std::max(start, std::min(pending_end_, next_start));
  const float strength = std::clamp(pending_map_.strength, 0.0f, 1.0f);
  if (pending_map_.count == 2) {
    const double split = std::clamp(static_cast<double>(pending_map_.split), 0.0, 1.0);
    // A stop's lead is closure time for its first viseme, so its split is
    // measured from the reported release; a vowel's lead is its true start.
    const double from = pending_map_.has(F::kVowel) ? start : pending_reported_;
    const double middle = std::clamp(from + split * (end - from), start, end);
    out[0] = {Seconds(start), Seconds(middle), pending_map_.visemes[0], strength};
    out[1] = {Seconds(middle), Seconds(end), pending_map_.visemes[1], strength};
    return 2;
  }
  out[0] = {Seconds(start), Seconds(end), pending_map_.visemes[0], strength};
  return 1;
}

std::vector<VisemeKey> PhonemesToVisemeKeys(std::span<const Phoneme> phonemes,
                                            const VisemeTimingParams& params) {
  std::vector<VisemeKey> keys;
  keys.reserve(phonemes.size() * kMaxVisemeKeysPerPhoneme);
  VisemeKeyStream stream(params);
  std::array<VisemeKey, kMaxVisemeKeysPerPhoneme> buffer{};
  for (const Phoneme& phoneme : phonemes) {
    const std::size_t n = *stream.Push(phoneme, buffer);
    keys.insert(keys.end(), buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n));
  }
  const std::size_t n = *stream.Finish(buffer);
  keys.insert(keys.end(), buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n));
  return keys;
}

}  // namespace facerig
