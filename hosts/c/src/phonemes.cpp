// fr_phoneme <-> facerig::Phoneme, for libfacerig and libfacerig_espeak.
#include <cmath>
#include <cstring>

#include "boundary.h"
#include "handles.h"

namespace facerig::capi {
namespace {

bool Terminated(const char (&name)[FR_NAME_CAPACITY]) {
  return std::memchr(name, '\0', FR_NAME_CAPACITY) != nullptr;
}

}  // namespace

fr_phoneme ToC(const Phoneme& phoneme) {
  fr_phoneme out{};
  out.start = phoneme.start.count();
  out.duration = phoneme.duration.count();
  CopyName(phoneme.symbol.view(), out.symbol);
  CopyName(phoneme.language.view(), out.language);
  out.word_start = phoneme.word_start ? 1 : 0;
  return out;
}

fr_status FromC(const fr_phoneme& in, Phoneme* out) {
  if (!std::isfinite(in.start) || !std::isfinite(in.duration) || in.start < 0.0 || in.duration < 0.0) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, "a phoneme's start or duration is negative, NaN or infinite");
  }
  if (!Terminated(in.symbol) || !Terminated(in.language)) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, "a phoneme's symbol or language has no terminating NUL");
  }
  if (std::strlen(in.symbol) > 8) return Fail(FR_ERROR_INVALID_ARGUMENT, {"phoneme symbol \"", in.symbol, "\" is longer than 8 bytes"});
  out->start = Seconds(in.start);
  out->duration = Seconds(in.duration);
  out->symbol.assign(in.symbol);
  out->language.assign(in.language);
  out->word_start = in.word_start != 0;
  return FR_OK;
}

}  // namespace facerig::capi
