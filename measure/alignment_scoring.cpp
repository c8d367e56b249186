#include "measure/alignment_scoring.h"

#include <algorithm>
#include <cmath>

#include "facerig/runtime/speech/phoneme_visemes.h"

namespace facerig::test {
namespace {

bool IsBilabial(const Phoneme& phoneme, std::string_view language) {
  const auto visemes = LookupPhonemeVisemes(language, phoneme.symbol.view());
  return visemes && visemes->count > 0 && visemes->visemes[0] == Viseme::kPP;
}

}  // namespace

AlignmentScore ScoreAlignment(const SpeechLine& truth, const SpeechLine& aligned) {
  AlignmentScore score;
  score.same_phonemes = truth.phonemes.size() == aligned.phonemes.size() &&
                        std::equal(truth.phonemes.begin(), truth.phonemes.end(), aligned.phonemes.begin(),
                                   [](const Phoneme& a, const Phoneme& b) { return a.symbol == b.symbol; });
  if (!score.same_phonemes) return score;
  for (std::size_t i = 0; i < truth.phonemes.size(); ++i) {
    const Phoneme& t = truth.phonemes[i];
    const Phoneme& a = aligned.phonemes[i];
    if (t.start.count() > 0.0) score.boundary_errors.push_back(std::abs(a.start.count() - t.start.count()));
    const std::string_view language = t.language.empty() ? truth.language.view() : t.language.view();
    if (!IsBilabial(t, language)) continue;
    ++score.bilabials;
    const double overlap =
        std::min(a.start + a.duration, t.start + t.duration).count() - std::max(a.start, t.start).count();
    if (IsBilabial(a, language) && overlap > 0.0) ++score.bilabials_kept;
  }
  return score;
}

double Quantile(std::vector<double> values, double share) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<std::size_t>(std::lround(share * static_cast<double>(values.size() - 1)));
  return values[rank];
}

}  // namespace facerig::test
