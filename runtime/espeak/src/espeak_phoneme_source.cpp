#include "facerig/espeak/espeak_phoneme_source.h"

#include <espeak-ng/speak_lib.h>

#include <algorithm>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <mutex>
#include <span>
#include <thread>
#include <utility>

namespace facerig {
namespace {

// Audio per synth callback, in ms (espeak-ng's default and minimum).
constexpr int kBufferMs = 60;
// espeak-ng allocates (buffer_ms * 200 / 1000 + 20) events per callback and
// silently drops markers once n - 2 are filled (MarkerEvent in speech.c). A
// callback that reaches this count may have lost events.
constexpr int kEventCapacity = kBufferMs * 200 / 1000 + 20 - 2;

std::string Lowercase(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c == '_') c = '-';
  }
  return out;
}

// Collects one line's events and audio, forwarding them to a receiver in the
// order documented in the header. Lives on the worker thread only.
class LineCollector {
 public:
  LineCollector(SpeechStreamReceiver& receiver, std::string_view language)
      : receiver_(receiver), language_(language) {}

  int OnCallback(short* wav, int sample_count, espeak_EVENT* events) {
    try {
      const std::size_t before = samples_;
      const std::size_t count = sample_count > 0 && wav ? static_cast<std::size_t>(sample_count) : 0;
      int event_count = 0;
      // The list ends with LIST_TERMINATED; the bound only guards against a
      // list without one.
      for (espeak_EVENT* event = events;
           event && event->type != espeakEVENT_LIST_TERMINATED && event_count < 100000;
           ++event, ++event_count) {
        if (event->type == espeakEVENT_WORD) {
          word_pending_ = true;
        } else if (event->type == espeakEVENT_PHONEME) {
          OnPhonemeEvent(*event, before, count);
        }
      }
      if (event_count >= kEventCapacity) overflow_ = true;
      if (count > 0) {
        receiver_.OnAudio(std::span<const std::int16_t>(wav, count));
        samples_ += count;
      }
      return 0;
    } catch (...) {
      error_ = std::current_exception();
      return 1;  // abort synthesis
    }
  }

  // Delivers the last phoneme (it runs to the end of the audio).
  void Finish() {
    if (has_pending_) {
      const Seconds end = SamplesToSeconds(samples_, EspeakPhonemeSource::kSampleRate);
      pending_.duration = std::max(Seconds(0.0), end - pending_.start);
      receiver_.OnPhoneme(pending_);
      has_pending_ = false;
    }
  }

  bool overflow() const { return overflow_; }
  const std::exception_ptr& error() const { return error_; }

 private:
  void OnPhonemeEvent(const espeak_EVENT& event, std::size_t before, std::size_t count) {
    // id.string is 8 bytes, zero-terminated only when shorter.
    char name[sizeof(event.id.string) + 1] = {};
    std::size_t length = 0;
    while (length < sizeof(event.id.string) && event.id.string[length] != '\0') {
      name[length] = event.id.string[length];
      ++length;
    }
    if (length == 0) return;
    const std::string_view symbol(name, length);
    if (symbol.front() == '(') {
      // "(en)": the following phonemes belong to another language's table.
      const std::size_t close = symbol.find(')');
      current_.assign(symbol.substr(1, close == std::string_view::npos ? close : close - 1));
      return;
    }
    // `sample` counts from the start of the synthesis call and does not reset
    // between sentences. Older espeak builds kept counting across calls: the
    // first event then lies beyond this buffer, which gives the offset.
    const long sample = event.sample;
    if (!base_known_) {
      base_known_ = true;
      if (sample > static_cast<long>(before + count)) base_ = sample - static_cast<long>(before);
    }
    const long relative = std::max(0L, sample - base_);
    Seconds start = SamplesToSeconds(static_cast<std::size_t>(relative), EspeakPhonemeSource::kSampleRate);
    if (has_pending_) {
      start = std::max(start, pending_.start);
      pending_.duration = start - pending_.start;
      receiver_.OnPhoneme(pending_);
    }
    pending_ = Phoneme{};
    pending_.start = start;
    pending_.symbol.assign(symbol);
    pending_.language = current_.empty() ? language_ : current_;
    // A word's WORD event may come just before the pause that ends the
    // previous clause: pauses never start words, the flag waits for a sound.
    const bool pause = symbol.front() == '_' || symbol == "||";
    pending_.word_start = word_pending_ && !pause;
    if (!pause) word_pending_ = false;
    has_pending_ = true;
  }

  SpeechStreamReceiver& receiver_;
  LanguageName language_;
  LanguageName current_;  // language switched to inside the line; empty: the voice's
  std::size_t samples_ = 0;
  long base_ = 0;
  bool base_known_ = false;
  bool word_pending_ = false;
  bool has_pending_ = false;
  Phoneme pending_;
  bool overflow_ = false;
  std::exception_ptr error_;
};

LineCollector* g_collector = nullptr;  // worker thread only

int SynthCallback(short* wav, int sample_count, espeak_EVENT* events) {
  return g_collector ? g_collector->OnCallback(wav, sample_count, events) : 0;
}

// The process-wide engine: one worker thread owns espeak-ng and runs tasks in
// order. Tasks throw SpeechError; the exception reaches the caller.
class Engine {
 public:
  static Engine& Instance() {
    static Engine engine;
    return engine;
  }

  template <typename Function>
  auto Run(Function function) -> decltype(function()) {
    using Result = decltype(function());
    auto task = std::make_shared<std::packaged_task<Result()>>(std::move(function));
    std::future<Result> future = task->get_future();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.emplace_back([task] { (*task)(); });
    }
    wake_.notify_one();
    return future.get();
  }

  // Worker thread only.
  void Initialize(const std::string& data_path) {
    if (initialized_) {
      if (!data_path.empty() && data_path != requested_path_) {
        throw SpeechError("espeak-ng is already initialised with data from \"" + data_path_ +
                          "\"; cannot switch to \"" + data_path + "\" in the same process");
      }
      return;
    }
    std::error_code error;
    if (!data_path.empty() && !std::filesystem::is_directory(data_path, error)) {
      throw SpeechError("espeak-ng data folder not found: \"" + data_path +
                        "\" (expected a folder holding espeak-ng-data, or espeak-ng-data itself)");
    }
    const int rate = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, kBufferMs,
                                       data_path.empty() ? nullptr : data_path.c_str(),
                                       espeakINITIALIZE_PHONEME_EVENTS | espeakINITIALIZE_DONT_EXIT);
    const char* info_path = nullptr;
    const char* version = espeak_Info(&info_path);
    const std::string tried = data_path.empty()
                                  ? std::string("the default location \"") +
                                        (info_path ? info_path : "?") + "\""
                                  : "\"" + data_path + "\"";
    if (rate <= 0) {
      throw SpeechError("espeak-ng could not load its data from " + tried +
                        " (espeak_Initialize returned " + std::to_string(rate) +
                        "); install espeak-ng-data or pass EspeakOptions::data_path");
    }
    if (rate != EspeakPhonemeSource::kSampleRate) {
      throw SpeechError("espeak-ng data from " + tried + " has sample rate " +
                        std::to_string(rate) + " Hz; facerig expects " +
                        std::to_string(EspeakPhonemeSource::kSampleRate));
    }
    espeak_SetSynthCallback(&SynthCallback);
    voices_ = ListVoices();
    data_path_ = info_path ? info_path : data_path;
    requested_path_ = data_path;
    version_ = version ? version : "";
    initialized_ = true;
  }

  // Worker thread only. A voice "xx" with a variant is loaded as "xx+variant";
  // espeak-ng silently ignores a variant it cannot find, so its file is checked first.
  void SetVoice(const std::string& voice, const std::string& variant) {
    if (!variant.empty()) {
      const std::string name = voice + "+" + variant;
      std::error_code error;
      const bool exists = variant.find_first_of("+/\\") == std::string::npos && variant != ".." &&
                          std::filesystem::is_regular_file(
                              std::filesystem::path(data_path_) / "voices" / "!v" / variant, error);
      if (!exists || espeak_SetVoiceByName(name.c_str()) != EE_OK) {
        throw SpeechError("espeak-ng has no voice variant \"" + variant + "\" (in " + data_path_ +
                          "/voices/!v) for \"" + name + "\"");
      }
      return;
    }
    if (espeak_SetVoiceByName(voice.c_str()) != EE_OK) {
      espeak_VOICE spec{};
      spec.languages = voice.c_str();
      if (espeak_SetVoiceByProperties(&spec) != EE_OK) {
        throw SpeechError("espeak-ng could not load the voice \"" + voice + "\"");
      }
    }
  }

  // Worker thread only; after Initialize.
  void Synthesize(const std::string& text, const std::string& voice, const EspeakOptions& options,
                  SpeechStreamReceiver& receiver) {
    SetVoice(voice, options.variant);
    espeak_SetParameter(espeakRATE, std::clamp(options.rate_wpm, espeakRATE_MINIMUM, espeakRATE_MAXIMUM),
                        0);
    espeak_SetParameter(espeakPITCH, std::clamp(options.pitch, 0, 100), 0);
    receiver.OnStart(EspeakPhonemeSource::kSampleRate);
    if (text.find_first_not_of(" \t\n") == std::string::npos) {
      receiver.OnEnd();
      return;
    }
    LineCollector collector(receiver, voice);
    g_collector = &collector;
    const espeak_ERROR result = espeak_Synth(text.c_str(), text.size() + 1, 0, POS_CHARACTER, 0,
                                             espeakCHARS_UTF8, nullptr, nullptr);
    g_collector = nullptr;
    if (collector.error()) std::rethrow_exception(collector.error());
    if (result != EE_OK) {
      throw SpeechError("espeak-ng failed to synthesize (espeak_Synth returned " +
                        std::to_string(static_cast<int>(result)) + ")");
    }
    if (collector.overflow()) {
      // Cannot tell which phonemes were lost; a track with holes would
      // animate the wrong mouth, so refuse it.
      throw SpeechError("espeak-ng's event list overflowed (" + std::to_string(kEventCapacity) +
                        " events in one audio buffer): phonemes may be missing; split the text");
    }
    collector.Finish();
    receiver.OnEnd();
  }

  const std::vector<std::string>& voices() const { return voices_; }
  const std::string& data_path() const { return data_path_; }
  const std::string& version() const { return version_; }

 private:
  Engine() : worker_([this] { Loop(); }) {}

  ~Engine() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.emplace_back([this] {
        if (initialized_) espeak_Terminate();
        initialized_ = false;
      });
      stop_ = true;
    }
    wake_.notify_one();
    worker_.join();
  }

  void Loop() {
    for (;;) {
      std::function<void()> task;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
        if (queue_.empty()) return;
        task = std::move(queue_.front());
        queue_.pop_front();
      }
      task();  // packaged_task: exceptions go to the caller's future
    }
  }

  static std::vector<std::string> ListVoices() {
    std::vector<std::string> names;
    const espeak_VOICE** voices = espeak_ListVoices(nullptr);
    for (std::size_t i = 0; voices && voices[i]; ++i) {
      // languages: (priority byte, zero-terminated name)*, then a zero byte.
      const char* p = voices[i]->languages;
      while (p && *p != '\0') {
        ++p;
        const std::size_t length = std::strlen(p);
        if (length > 0) names.push_back(Lowercase(std::string_view(p, length)));
        p += length + 1;
      }
    }
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    return names;
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> queue_;
  bool stop_ = false;
  // Worker-thread state.
  bool initialized_ = false;
  std::string requested_path_;
  std::string data_path_;
  std::string version_;
  std::vector<std::string> voices_;
  std::thread worker_;  // last: starts once the members above exist
};

// Collects a whole line (schedule-ahead mode).
class LineBuilder final : public SpeechStreamReceiver {
 public:
  explicit LineBuilder(SpeechLine& line) : line_(line) {}
  void OnStart(int sample_rate) override { line_.sample_rate = sample_rate; }
  void OnAudio(std::span<const std::int16_t> samples) override {
    line_.audio.insert(line_.audio.end(), samples.begin(), samples.end());
  }
  void OnPhoneme(const Phoneme& phoneme) override { line_.phonemes.push_back(phoneme); }
  void OnEnd() override {}

 private:
  SpeechLine& line_;
};

std::string CheckVoice(std::string_view voice, const std::vector<std::string>& voices) {
  const std::string name = Lowercase(voice);
  if (std::binary_search(voices.begin(), voices.end(), name)) return name;
  std::string message = "unknown espeak-ng voice \"" + std::string(voice) + "\"; available:";
  for (const std::string& v : voices) message.append(" ").append(v);
  throw SpeechError(message);
}

std::string CheckText(std::string_view text) {
  if (text.size() > EspeakPhonemeSource::kMaxTextBytes) {
    throw SpeechError("text of " + std::to_string(text.size()) + " bytes is longer than " +
                      std::to_string(EspeakPhonemeSource::kMaxTextBytes) +
                      " bytes (EspeakPhonemeSource::kMaxTextBytes); split it into lines");
  }
  return SanitizeSpeechText(text);
}

}  // namespace

std::string SanitizeSpeechText(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x80) {
      const bool control = (byte < 0x20 && byte != '\n' && byte != '\t') || byte == 0x7F;
      out.push_back(control ? ' ' : static_cast<char>(byte));
      ++i;
      continue;
    }
    // Multi-byte: the lead byte gives the length and the valid range of the
    // second byte (no overlong forms, no surrogates, nothing above U+10FFFF).
    std::size_t length = 0;
    unsigned char low = 0x80, high = 0xBF;
    if (byte >= 0xC2 && byte <= 0xDF) {
      length = 2;
    } else if (byte >= 0xE0 && byte <= 0xEF) {
      length = 3;
      if (byte == 0xE0) low = 0xA0;
      if (byte == 0xED) high = 0x9F;
    } else if (byte >= 0xF0 && byte <= 0xF4) {
      length = 4;
      if (byte == 0xF0) low = 0x90;
      if (byte == 0xF4) high = 0x8F;
    }
    bool valid = length > 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      valid = k == 1 ? next >= low && next <= high : next >= 0x80 && next <= 0xBF;
    }
    if (!valid) {
      out.push_back(' ');
      ++i;
      continue;
    }
    // C1 controls (U+0080..U+009F) are two bytes, C2 80..C2 9F.
    const bool c1_control = byte == 0xC2 && static_cast<unsigned char>(text[i + 1]) <= 0x9F;
    if (c1_control) {
      out.push_back(' ');
    } else {
      out.append(text.substr(i, length));
    }
    i += length;
  }
  return out;
}

EspeakPhonemeSource::EspeakPhonemeSource(EspeakOptions options) : options_(std::move(options)) {
  Engine& engine = Engine::Instance();
  voices_ = engine.Run([&engine, path = options_.data_path] {
    engine.Initialize(path);
    return engine.voices();
  });
}

EspeakPhonemeSource::~EspeakPhonemeSource() = default;

SpeechLine EspeakPhonemeSource::Synthesize(std::string_view text, std::string_view voice) {
  Engine& engine = Engine::Instance();
  const std::string name = CheckVoice(voice, voices_);
  std::string sanitized = CheckText(text);
  SpeechLine line;
  line.text = std::string(text);
  line.language.assign(name);
  LineBuilder builder(line);
  engine.Run([&] { engine.Synthesize(sanitized, name, options_, builder); });
  return line;
}

void EspeakPhonemeSource::SynthesizeStreaming(std::string_view text, std::string_view voice,
                                              SpeechStreamReceiver& receiver) {
  Engine& engine = Engine::Instance();
  const std::string name = CheckVoice(voice, voices_);
  std::string sanitized = CheckText(text);
  engine.Run([&] { engine.Synthesize(sanitized, name, options_, receiver); });
}

std::vector<std::string> EspeakPhonemeSource::Voices() const { return voices_; }

std::string EspeakPhonemeSource::DataPath() const {
  Engine& engine = Engine::Instance();
  return engine.Run([&engine] { return engine.data_path(); });
}

std::string EspeakPhonemeSource::Version() const {
  Engine& engine = Engine::Instance();
  return engine.Run([&engine] { return engine.version(); });
}

}  // namespace facerig
