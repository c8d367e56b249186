// espeak-ng as a phoneme source (facerig::espeak; espeak-ng is GPL-3).
//
// espeak-ng is one global engine per process. Every EspeakPhonemeSource
// shares it: one worker thread owns the engine and runs one line at a time,
// so any number of threads (characters) may call Synthesize concurrently;
// calls queue behind each other. Each line gets its own audio buffer and
// phoneme track.
//
// Phonemes are espeak-ng's own names (e.g. "aI", "tS", "@L"), timed from the
// events' sample positions (exact in the returned audio). A phoneme's
// duration runs to the next phoneme's start (the last one: to the end of the
// audio). Zero-length events (pause markers, some consonants) keep duration
// 0. Language switches inside a line (espeak's "(en)" events, e.g. the
// Mandarin voice spelling Latin text) are not phonemes: they set the
// `language` of the phonemes that follow.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/speech/phoneme_source.h"

namespace facerig {

struct EspeakOptions {
  // Folder holding espeak-ng-data (or that folder itself); empty: espeak-ng's
  // default (ESPEAK_DATA_PATH, then the installed data). The engine is
  // initialised once per process: a later source asking for another folder
  // gets a SpeechError.
  std::string data_path;
  // Speaking rate in words per minute (espeak-ng accepts 80..450).
  int rate_wpm = 175;
  // Base pitch, 0..100 (espeak-ng's default 50).
  int pitch = 50;
  // An espeak-ng voice variant (a file in espeak-ng-data/voices/!v, e.g. "f3",
  // "m2", "klatt"): another speaker for the same language and phonemes. Empty:
  // the language's own voice. An unknown variant gives a SpeechError.
  std::string variant;
};

class EspeakPhonemeSource final : public PhonemeSource {
 public:
  // espeak-ng's output sample rate, checked at initialisation.
  static constexpr int kSampleRate = 22050;
  // Longest text accepted per line, in bytes (about 15 minutes of speech,
  // 40 MB of audio); longer text is refused with a SpeechError. Split longer
  // text into lines.
  static constexpr std::size_t kMaxTextBytes = 16 * 1024;

  // Initialises the shared engine on first use. Throws SpeechError when the
  // data folder is missing or espeak-ng cannot load its data (the message
  // names the folder tried), never exits the process.
  explicit EspeakPhonemeSource(EspeakOptions options = {});
  ~EspeakPhonemeSource() override;
  EspeakPhonemeSource(const EspeakPhonemeSource&) = delete;
  EspeakPhonemeSource& operator=(const EspeakPhonemeSource&) = delete;

  // `voice` is a language name as listed by Voices() ("en-us", "pt-br", "cmn";
  // case-insensitive, '_' accepted for '-'); an unknown voice throws a
  // SpeechError listing the available ones. The text is sanitised: invalid
  // UTF-8 and control characters (except newline and tab) become spaces.
  // Empty (or all-blank) text gives an empty line with no audio. Text longer
  // than kMaxTextBytes throws SpeechError.
  SpeechLine Synthesize(std::string_view text, std::string_view voice) override;

  // Streaming: OnStart, then phonemes and audio chunks from the worker
  // thread as espeak-ng produces them (much faster than real time), then
  // OnEnd. A phoneme is delivered once its duration is known, i.e. when the
  // next phoneme's event arrives (the last one before OnEnd); each chunk of
  // audio is delivered after the phonemes completed within it. The phonemes
  // are those Synthesize returns for the same text and voice, their times
  // those of this call's audio (espeak-ng's durations vary slightly with
  // what it synthesized before, in its audio as in its events). A receiver
  // that throws aborts the line; the exception is rethrown to the caller.
  // The receiver must not call back into an EspeakPhonemeSource (deadlock).
  void SynthesizeStreaming(std::string_view text, std::string_view voice,
                           SpeechStreamReceiver& receiver) override;

  // Language names of the installed voices, sorted ("af", ..., "en-us", ...).
  std::vector<std::string> Voices() const override;

  // The espeak-ng data folder in use and the library version.
  std::string DataPath() const;
  std::string Version() const;

 private:
  EspeakOptions options_;
  std::vector<std::string> voices_;  // the engine's list, copied once
};

// Replaces invalid UTF-8 sequences and control characters (except '\n' and
// '\t') by spaces; what EspeakPhonemeSource does to its input.
std::string SanitizeSpeechText(std::string_view text);

}  // namespace facerig
