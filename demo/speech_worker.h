// Synthesizes lines on a worker thread so the window keeps drawing while
// espeak-ng runs (the engine itself is already behind its own thread; this
// keeps the render loop from blocking on it).
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "facerig/runtime/speech/phoneme.h"

namespace facerig::player {

struct SpeechResult {
  std::string text;
  SpeechLine line;
  std::string error;  // SpeechError message (e.g. unknown voice, listing the voices); empty on success
};

class SpeechWorker {
 public:
  SpeechWorker();
  ~SpeechWorker();  // finishes the line in progress, drops the rest
  SpeechWorker(const SpeechWorker&) = delete;
  SpeechWorker& operator=(const SpeechWorker&) = delete;

  void Request(std::string text, std::string voice);
  // A finished line, if any (render thread, once per frame).
  std::optional<SpeechResult> Poll();
  bool busy() const;

 private:
  void Run();

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::pair<std::string, std::string>> requests_;
  std::deque<SpeechResult> results_;
  bool working_ = false;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace facerig::player
