#include "speech_worker.h"

#include <exception>
#include <memory>

#include "facerig/espeak/espeak_phoneme_source.h"

namespace facerig::player {

SpeechWorker::SpeechWorker() : thread_([this] { Run(); }) {}

SpeechWorker::~SpeechWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    requests_.clear();
  }
  wake_.notify_all();
  thread_.join();
}

void SpeechWorker::Request(std::string text, std::string voice) {
  {
    std::lock_guard lock(mutex_);
    requests_.emplace_back(std::move(text), std::move(voice));
  }
  wake_.notify_all();
}

std::optional<SpeechResult> SpeechWorker::Poll() {
  std::lock_guard lock(mutex_);
  if (results_.empty()) return std::nullopt;
  SpeechResult result = std::move(results_.front());
  results_.pop_front();
  return result;
}

bool SpeechWorker::busy() const {
  std::lock_guard lock(mutex_);
  return working_ || !requests_.empty();
}

void SpeechWorker::Run() {
  std::unique_ptr<EspeakPhonemeSource> source;  // created on first use (it loads espeak-ng's data)
  for (;;) {
    std::pair<std::string, std::string> request;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !requests_.empty(); });
      if (stop_) return;
      request = std::move(requests_.front());
      requests_.pop_front();
      working_ = true;
    }
    SpeechResult result;
    result.text = request.first;
    try {
      if (!source) source = std::make_unique<EspeakPhonemeSource>();
      result.line = source->Synthesize(request.first, request.second);
    } catch (const std::exception& e) {
      result.error = e.what();
    }
    std::lock_guard lock(mutex_);
    results_.push_back(std::move(result));
    working_ = false;
  }
}

}  // namespace facerig::player
