// Phonemes from audio in chunks: the rough mode (RoughMouthStream) or
// streaming alignment to a synthesised transcript (StreamingAligner).
#include <algorithm>

#include "boundary.h"
#include "facerig/runtime/io/audio_file.h"
#include "handles.h"

namespace facerig::capi {
namespace {

// Aligned mode: a boundary gives reference phoneme i its recording start;
// phoneme i - 1 is then final, lasting up to it.
void TakeBoundaries(fr_audio_stream& stream, std::span<const StreamedBoundary> boundaries) {
  for (const StreamedBoundary& boundary : boundaries) {
    if (boundary.phoneme >= stream.reference.size()) continue;
    stream.reference[boundary.phoneme].start = boundary.start;
    for (; stream.timed < boundary.phoneme; ++stream.timed) {
      Phoneme& done = stream.reference[stream.timed];
      done.duration = std::max(Seconds(0.0), boundary.start - done.start);
      stream.ready.push_back(done);
    }
    stream.timed = boundary.phoneme;
  }
}

// The read position moves over `ready`; drop what was read before adding.
void Compact(fr_audio_stream& stream) {
  if (stream.read == 0) return;
  stream.ready.erase(stream.ready.begin(), stream.ready.begin() + static_cast<std::ptrdiff_t>(stream.read));
  stream.read = 0;
}

}  // namespace
}  // namespace facerig::capi

using namespace facerig::capi;

extern "C" {

fr_status fr_audio_stream_create_rough(int32_t sample_rate, fr_audio_stream** out_stream) {
  return Guard([&] {
    FR_REQUIRE(out_stream, "out_stream");
    *out_stream = nullptr;
    auto stream = std::make_unique<fr_audio_stream>();
    stream->rough.emplace(sample_rate);
    if (!stream->rough->valid()) {
      return Fail(FR_ERROR_INVALID_ARGUMENT, {"sample rate ", std::to_string(sample_rate),
                                              " Hz is outside what the rough mode reads (4000-384000)"});
    }
    *out_stream = stream.release();
    return FR_OK;
  });
}

fr_status fr_audio_stream_create_aligned(const fr_speech* reference, fr_audio_stream** out_stream) {
  return Guard([&] {
    FR_REQUIRE(out_stream, "out_stream");
    *out_stream = nullptr;
    FR_REQUIRE(reference, "reference");
    facerig::SpeechLine line = reference->line;
    line.sample_rate = reference->sample_rate;
    line.audio = facerig::FloatToPcm(reference->samples);
    auto stream = std::make_unique<fr_audio_stream>();
    stream->aligner = std::make_unique<facerig::StreamingAligner>(line);  // AlignmentError: FR_ERROR_SPEECH
    stream->reference = std::move(line.phonemes);
    *out_stream = stream.release();
    return FR_OK;
  });
}

fr_status fr_audio_stream_push(fr_audio_stream* stream, const float* samples, size_t sample_count) {
  return Guard([&] {
    FR_REQUIRE(stream, "stream");
    if (samples == nullptr && sample_count > 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "samples is NULL");
    const std::span<const float> chunk(samples, sample_count);
    Compact(*stream);
    if (stream->rough) {
      stream->rough->Push(chunk, stream->ready);
      return FR_OK;
    }
    if (stream->finished) return Fail(FR_ERROR_STATE, "the aligned stream was finished: make a new one");
    TakeBoundaries(*stream, stream->aligner->Push(chunk));
    return FR_OK;
  });
}

fr_status fr_audio_stream_finish(fr_audio_stream* stream) {
  return Guard([&] {
    FR_REQUIRE(stream, "stream");
    Compact(*stream);
    if (stream->rough) {
      stream->rough->Finish(stream->ready);
      return FR_OK;
    }
    if (stream->finished) return FR_OK;
    stream->finished = true;
    TakeBoundaries(*stream, stream->aligner->Finish());
    // The last phoneme keeps the reference's duration.
    for (; stream->timed < stream->reference.size(); ++stream->timed) {
      stream->ready.push_back(stream->reference[stream->timed]);
    }
    return FR_OK;
  });
}

fr_status fr_audio_stream_read(fr_audio_stream* stream, fr_phoneme* phonemes, size_t capacity, size_t* written) {
  FR_REQUIRE(stream, "stream");
  FR_REQUIRE(written, "written");
  *written = 0;
  if (capacity > 0) FR_REQUIRE(phonemes, "phonemes");
  const std::size_t n = std::min(capacity, stream->ready.size() - stream->read);
  for (std::size_t i = 0; i < n; ++i) phonemes[i] = ToC(stream->ready[stream->read + i]);
  stream->read += n;
  *written = n;
  return FR_OK;
}

void fr_audio_stream_release(fr_audio_stream* stream) { delete stream; }

}  // extern "C"
