// The headless player's outputs (frames folder, WAV, MP4, timing JSON) as one
// set: each is written under a temporary name in its destination folder and
// all are renamed into place together at the end, so a failed or killed run
// leaves the previous complete set or the new one, never a mix.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace facerig::player {

// Every temporary name starts with this, followed by the writing process's id
// and '-': ".facerig-tmp-1234-player.wav". The next run in the same folder
// removes those whose process is gone.
inline constexpr std::string_view kTemporaryPrefix = ".facerig-tmp-";

class OutputSet {
 public:
  enum class Kind { kFile, kFolder };

  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet();  // removes the temporaries unless committed

  // Registers `final_path` and returns the temporary path to write it to (a
  // new empty folder for kFolder). Removes stale temporaries of killed runs in
  // its folder first. An existing folder is replaced at Commit(), so it must
  // hold nothing but frame_NNNNN.png files. Throws std::runtime_error.
  std::filesystem::path Add(const std::filesystem::path& final_path, Kind kind);

  // Renames every temporary over its final path (an existing folder is
  // replaced, not merged) and removes the previous outputs. If one rename
  // fails, those already done are undone and the temporaries removed; throws
  // std::runtime_error naming the path and the reason.
  void Commit();
  // Removes every temporary (also on Commit() failure and in the destructor).
  void Abandon() noexcept;

  // `message` with each temporary path replaced by its final path as given to Add(),
  // so that errors name the file the user asked for.
  std::string WithFinalPaths(std::string message) const;

 private:
  struct Entry {
    std::filesystem::path final_path, temporary;  // both absolute
    std::filesystem::path given;                  // final_path as given to Add()
    Kind kind = Kind::kFile;
  };
  // What Place() did to one entry, so that Commit() can undo it.
  enum class Placed { kNothing, kNew, kExchanged, kAside, kAsideOnly };
  void RemoveStaleTemporaries(const std::filesystem::path& folder);
  static std::error_code Place(const Entry& entry, Placed* placed);
  static std::error_code Unplace(const Entry& entry, Placed placed);
  static std::filesystem::path AsidePath(const Entry& entry);

  std::vector<Entry> entries_;
  std::vector<std::filesystem::path> cleaned_folders_;
  bool committed_ = false;
};

// Test hook: true when the comma-separated list in the environment variable
// FACERIG_PLAYER_INJECT_FAILURE holds `what`: "wav" (the WAV write runs out of
// space part-way), "rename" (the last rename of Commit() fails), "no-exchange"
// (Commit() acts as on a file system without an atomic exchange).
bool FailureInjected(std::string_view what);

}  // namespace facerig::player
