// Outputs written as one set (the player's frames, WAV, MP4 and timing JSON;
// `facerig build`'s rig, .frig, OBJ folder and report; `facerig
// default-head`'s files): each is written under a temporary name in its
// destination folder and all are renamed into place together at the end, so
// a failed or stopped run leaves the previous complete set or the new one,
// never a mix. Only a kill (SIGKILL, power loss) in the instant of the renames
// themselves can leave a mix. A file output may go directly inside a folder
// output (the player's `--frames out/ --wav out/speech.wav`): it is written
// inside the folder's temporary and arrives with it.
//
// Missing folders are not created: an output's folder must exist (a folder
// output itself is created, in a folder that exists), so that a mistyped
// path fails at once, before any work, naming the path as given.
#pragma once

#include <signal.h>

#include <csignal>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace facerig {

// Every temporary name starts with this, followed by the writing process's id
// and '-': ".facerig-tmp-1234-player.wav". The next run in the same folder
// removes those whose process is gone.
inline constexpr std::string_view kTemporaryPrefix = ".facerig-tmp-";

// The name a temporary stands for (".facerig-tmp-1234-face.glb" -> "face.glb"),
// for writers that record their own file name; other names as they are.
std::string FinalFileName(std::string_view file_name);

// What an existing folder may hold for a kFolder output to replace it, so that
// a folder of the user's own files is never thrown away: every entry must be a
// regular file for which `holds` is true ("frame_NNNNN.png files", for the
// option "--frames"). Without `holds`, only an empty folder is replaced.
struct ReplaceableFolder {
  std::function<bool(const std::filesystem::path& file_name)> holds;
  std::string description;  // what `holds` accepts, for the error
  std::string option;       // the option naming the folder, for the error
  // File names of this run's other outputs that go inside the folder (a WAV
  // beside the frames): replaced with it, so the previous ones may be there.
  // Each must be one `holds` refuses, so that it cannot overwrite one of the
  // folder's own files.
  std::vector<std::string> outputs_inside = {};
};

// Throws std::runtime_error naming `final_path` as given when an output
// cannot be written there: its folder does not exist, is not a folder, or
// this process may not create files in it. Checks nothing is written.
void CheckOutputFolder(const std::filesystem::path& final_path);

class OutputSet {
 public:
  enum class Kind { kFile, kFolder };

  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet();  // removes the temporaries unless committed

  // Registers `final_path` and returns the temporary path to write it to (a
  // new empty folder for kFolder). Checks its folder first
  // (CheckOutputFolder) and removes stale temporaries of killed runs there.
  // An existing folder is replaced at Commit(), so it must hold only what
  // `replaceable` accepts. The temporary keeps the final name's extension. A
  // file directly inside a folder output added before it gets a temporary
  // inside the folder's, under its own name; one the folder's `holds`
  // accepts (a frame's name) is refused. Throws std::runtime_error.
  std::filesystem::path Add(const std::filesystem::path& final_path, Kind kind,
                            const ReplaceableFolder& replaceable = {});

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
    ReplaceableFolder replaceable;                // kFolder: what it holds
    bool inside_folder = false;                   // written inside a folder output's temporary
  };
  // The folder output `entry` goes directly inside, or null; throws when it is inside one deeper.
  const Entry* FolderHolding(const Entry& entry) const;
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

// A run stopped by SIGINT or SIGTERM (see InstallStopSignalHandlers); a
// command exits with 128 + signal() after removing its temporaries.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};

// SIGINT and SIGTERM then only set a flag, which ThrowIfStopped() checks
// between a run's writes, so that its OutputSet removes the temporaries.
void InstallStopSignalHandlers();
// Throws Interrupted when SIGINT or SIGTERM arrived since InstallStopSignalHandlers().
void ThrowIfStopped();

// InstallStopSignalHandlers() for a scope (a command's writes, run in-process
// by the tests too); the previous handlers come back at its end.
class StopSignalScope {
 public:
  StopSignalScope();
  ~StopSignalScope();
  StopSignalScope(const StopSignalScope&) = delete;
  StopSignalScope& operator=(const StopSignalScope&) = delete;

 private:
  struct sigaction previous_interrupt_ {};
  struct sigaction previous_terminate_ {};
};

// Called after writing `written` (a temporary of an OutputSet): throws
// Interrupted after SIGINT or SIGTERM. Test hooks, by FailureInjected():
// "fail-STEP" makes the write of STEP fail as on a full disk, "term-after-STEP"
// and "kill-after-STEP" send the process SIGTERM or SIGKILL.
void CheckAfterWrite(std::string_view step, const std::filesystem::path& written);

// Test hook: true when the comma-separated list in the environment variable
// FACERIG_INJECT_FAILURE (or FACERIG_PLAYER_INJECT_FAILURE, the player's name
// for it) holds `what`. Shared ones: "rename" (the last rename of Commit()
// fails), "no-exchange" (Commit() acts as on a file system without an atomic
// exchange); the writers name their own (the player's "wav", "timing"; the
// build's in cli_build.cpp).
bool FailureInjected(std::string_view what);

}  // namespace facerig
