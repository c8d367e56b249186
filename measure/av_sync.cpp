#include "measure/av_sync.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "facerig/runtime/speech/phoneme_visemes.h"

namespace facerig::test {
namespace {

// Sum of squares of samples[first, last) from a prefix sum.
double Energy(const std::vector<double>& prefix, std::size_t first, std::size_t last) {
  return prefix[last] - prefix[first];
}

std::vector<double> SquarePrefix(std::span<const float> samples) {
  std::vector<double> prefix(samples.size() + 1, 0.0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    prefix[i + 1] = prefix[i] + static_cast<double>(samples[i]) * samples[i];
  }
  return prefix;
}

std::size_t SampleAt(double seconds, int rate, std::size_t size) {
  return static_cast<std::size_t>(std::clamp(std::lround(seconds * rate), 0L, static_cast<long>(size)));
}

}  // namespace

std::vector<double> RmsEnvelope(std::span<const float> samples, int rate, double step, double window) {
  const std::vector<double> prefix = SquarePrefix(samples);
  const double duration = static_cast<double>(samples.size()) / rate;
  std::vector<double> envelope;
  for (double t = 0.0; t < duration; t += step) {
    const std::size_t first = SampleAt(t - 0.5 * window, rate, samples.size());
    const std::size_t last = SampleAt(t + 0.5 * window, rate, samples.size());
    envelope.push_back(last > first ? std::sqrt(Energy(prefix, first, last) / static_cast<double>(last - first)) : 0.0);
  }
  return envelope;
}

std::vector<double> Interpolate(std::span<const double> series, double from_step, double to_step) {
  std::vector<double> out;
  if (series.empty()) return out;
  const double duration = static_cast<double>(series.size()) * from_step;
  for (double t = 0.0; t < duration; t += to_step) {
    const double at = t / from_step;
    const auto i = static_cast<std::size_t>(at);
    const double f = at - static_cast<double>(i);
    out.push_back(i + 1 < series.size() ? (1.0 - f) * series[i] + f * series[i + 1] : series.back());
  }
  return out;
}

namespace {

// Pearson correlation of sound[i] with mouth[i + shift] over the indices both hold.
double CorrelationAtShift(std::span<const double> sound, std::span<const double> mouth, long shift) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  long n = 0;
  for (long i = std::max(0L, -shift); i < static_cast<long>(sound.size()) && i + shift < static_cast<long>(mouth.size());
       ++i) {
    const double a = sound[static_cast<std::size_t>(i)], b = mouth[static_cast<std::size_t>(i + shift)];
    sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b;
    ++n;
  }
  if (n < 2) return 0.0;
  const auto count = static_cast<double>(n);
  const double cov = sab - sa * sb / count, va = saa - sa * sa / count, vb = sbb - sb * sb / count;
  return va > 0.0 && vb > 0.0 ? cov / std::sqrt(va * vb) : 0.0;
}

}  // namespace

LagPeak PeakLag(std::span<const double> sound, std::span<const double> mouth, double step, double max_lag) {
  LagPeak best{0.0, -2.0};
  const long steps = std::lround(max_lag / step);
  for (long shift = -steps; shift <= steps; ++shift) {
    const double r = CorrelationAtShift(sound, mouth, shift);
    if (r > best.correlation) best = {static_cast<double>(shift) * step, r};
  }
  return best;
}

double QuietestWindow(std::span<const float> samples, int rate, double from, double to, double window) {
  const std::vector<double> prefix = SquarePrefix(samples);
  const auto length = static_cast<std::size_t>(std::lround(window * rate));
  double best_start = from, best_energy = -1.0;
  for (double t = from; t <= to + 1e-9; t += 0.001) {
    const std::size_t first = SampleAt(t, rate, samples.size());
    if (first + length > samples.size()) break;
    const double energy = Energy(prefix, first, first + length);
    if (best_energy < 0.0 || energy < best_energy) best_energy = energy, best_start = t;
  }
  return best_start;
}

double BoxDifference(const FramePixels& frame, const FramePixels& first, const PixelBox& box) {
  double sum = 0.0;
  for (int y = box.y0; y < box.y1; ++y) {
    for (int x = box.x0; x < box.x1; ++x) {
      const std::size_t at = (static_cast<std::size_t>(y) * frame.width + x) * frame.channels;
      for (std::size_t c = 0; c < 3; ++c) sum += std::abs(frame.values[at + c] - first.values[at + c]);
    }
  }
  const int count = 3 * (box.x1 - box.x0) * (box.y1 - box.y0);
  return count > 0 ? sum / count : 0.0;
}

PixelBox ChangingLowerBox(std::span<const FramePixels> frames) {
  if (frames.empty()) return {};
  const FramePixels& first = frames.front();
  const int top = first.height / 2;
  std::vector<int> change(static_cast<std::size_t>(first.width) * first.height, 0);
  for (const FramePixels& frame : frames) {
    for (int y = top; y < first.height; ++y) {
      for (int x = 0; x < first.width; ++x) {
        const std::size_t pixel = static_cast<std::size_t>(y) * first.width + x;
        for (std::size_t c = 0; c < 3; ++c) {
          const std::size_t at = pixel * first.channels + c;
          change[pixel] = std::max(change[pixel], std::abs(frame.values[at] - first.values[at]));
        }
      }
    }
  }
  const int largest = *std::max_element(change.begin(), change.end());
  PixelBox box{first.width, first.height, 0, 0};
  for (int y = top; y < first.height && largest > 0; ++y) {
    for (int x = 0; x < first.width; ++x) {
      if (4 * change[static_cast<std::size_t>(y) * first.width + x] < largest) continue;
      box = {std::min(box.x0, x), std::min(box.y0, y), std::max(box.x1, x + 1), std::max(box.y1, y + 1)};
    }
  }
  return box.x1 > box.x0 ? box : PixelBox{};
}

std::vector<double> MouthSeries(std::span<const FramePixels> frames, const PixelBox& box) {
  std::vector<double> series;
  for (const FramePixels& frame : frames) series.push_back(BoxDifference(frame, frames.front(), box));
  return series;
}

LagPeak MouthLag(std::span<const double> mouth, double fps, std::span<const float> samples, int rate) {
  constexpr double kStep = 0.001;
  const std::vector<double> sound = RmsEnvelope(samples, rate, kStep, 1.0 / fps);
  const std::vector<double> fine_mouth = Interpolate(mouth, 1.0 / fps, kStep);
  return PeakLag(sound, fine_mouth, kStep, 0.150);
}

namespace {

Viseme FirstViseme(const Phoneme& p) {
  const auto visemes = LookupPhonemeVisemes("en-us", p.symbol.view());
  return visemes && visemes->count > 0 ? visemes->visemes[0] : Viseme::kSil;
}

bool IsVowel(const Phoneme& p) {
  const Viseme v = FirstViseme(p);
  return v == Viseme::kAA || v == Viseme::kE || v == Viseme::kIH || v == Viseme::kOH || v == Viseme::kOU;
}

// From the preceding vowel's middle to the next vowel's onset (150 ms from
// the phoneme where there is none), in recording time.
std::pair<double, double> VowelToVowel(std::span<const Phoneme> phonemes, std::size_t i) {
  double from = phonemes[i].start.count() - 0.150, to = phonemes[i].start.count() + 0.150;
  for (std::size_t j = i; j-- > 0;) {
    if (IsVowel(phonemes[j])) {
      from = (phonemes[j].start + 0.5 * phonemes[j].duration).count();
      break;
    }
  }
  for (std::size_t j = i + 1; j < phonemes.size(); ++j) {
    if (IsVowel(phonemes[j])) {
      to = phonemes[j].start.count();
      break;
    }
  }
  return {from, to};
}

// The frame with the least opening in [from, to] s and the frames around it
// at most `closed` open.
void LipsClosed(std::span<const double> mouth, double fps, double from, double to, double closed,
                BilabialClosure* c) {
  const auto first = static_cast<std::size_t>(std::max(0.0, std::floor(from * fps)));
  const auto last = std::min(mouth.size() - 1, static_cast<std::size_t>(std::ceil(to * fps)));
  std::size_t least = std::min(first, last);
  for (std::size_t f = least; f <= last; ++f) least = mouth[f] < mouth[least] ? f : least;
  std::size_t a = least, b = least;
  while (a > first && mouth[a - 1] <= closed) --a;
  while (b < last && mouth[b + 1] <= closed) ++b;
  c->lips_least_open = static_cast<double>(least) / fps;
  c->lips_from = (static_cast<double>(a) - 0.5) / fps;
  c->lips_to = (static_cast<double>(b) + 0.5) / fps;
}

}  // namespace

std::vector<BilabialClosure> MeasureBilabialClosures(std::span<const double> mouth, double fps,
                                                     std::span<const float> samples, int rate,
                                                     std::span<const Phoneme> phonemes, double offset) {
  std::vector<BilabialClosure> closures;
  if (mouth.empty()) return closures;
  const double widest = *std::max_element(mouth.begin(), mouth.end());
  for (std::size_t i = 0; i < phonemes.size(); ++i) {
    if (FirstViseme(phonemes[i]) != Viseme::kPP) continue;
    const auto [from, to] = VowelToVowel(phonemes, i);
    BilabialClosure c{std::string(phonemes[i].symbol.view())};
    c.acoustic_from = QuietestWindow(samples, rate, from + offset, std::max(from, to - 0.030) + offset, 0.030);
    c.acoustic_to = c.acoustic_from + 0.030;
    LipsClosed(mouth, fps, from + offset, to + offset, 0.15 * widest, &c);
    closures.push_back(c);
  }
  return closures;
}

}  // namespace facerig::test
