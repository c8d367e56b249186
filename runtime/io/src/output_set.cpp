#include "facerig/runtime/io/output_set.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <system_error>

#include "facerig/runtime/files/input_file.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

// Absolute, normalized, without a trailing separator: "out/frames/" -> "/cwd/out/frames".
fs::path OutputPath(const fs::path& path) {
  fs::path normal = fs::absolute(path).lexically_normal();
  if (!normal.has_filename()) normal = normal.parent_path();
  if (normal == normal.root_path()) throw std::runtime_error("cannot write an output over " + normal.string());
  return normal;
}

std::string TemporaryName(std::string_view tag, const fs::path& final_path) {
  return std::string(kTemporaryPrefix) + std::to_string(::getpid()) + "-" + std::string(tag) +
         final_path.filename().string();
}

}  // namespace

std::string FinalFileName(std::string_view file_name) {
  if (!file_name.starts_with(kTemporaryPrefix)) return std::string(file_name);
  const std::size_t dash = file_name.find('-', kTemporaryPrefix.size());
  return dash == std::string_view::npos ? std::string(file_name) : std::string(file_name.substr(dash + 1));
}

namespace {

// A temporary left by a process that no longer runs (or a name without a process id).
bool IsStale(const std::string& name) {
  if (name.rfind(kTemporaryPrefix, 0) != 0) return false;
  const char* digits = name.data() + kTemporaryPrefix.size();
  int pid = 0;
  const auto [end, error] = std::from_chars(digits, name.data() + name.size(), pid);
  if (error != std::errc() || *end != '-' || pid <= 0) return true;
  return pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

// The folder an output goes into, as the user wrote it: "out/speech.wav" -> "out".
std::string ShownFolder(const fs::path& given) {
  fs::path path = given.lexically_normal();
  if (!path.has_filename()) path = path.parent_path();
  path = path.parent_path();
  return path.empty() ? std::string(".") : path.string();
}

// A folder output is replaced as a whole: refuse to replace one that holds anything else.
void CheckReplaceableFolder(const fs::path& folder, const fs::path& given, const ReplaceableFolder& replaceable) {
  std::error_code error;
  if (!fs::exists(folder, error)) return;
  if (!fs::is_directory(folder, error)) throw std::runtime_error(given.string() + " exists and is not a folder");
  const auto is_output_inside = [&replaceable](const fs::path& name) {
    const auto& inside = replaceable.outputs_inside;
    return std::find(inside.begin(), inside.end(), name.string()) != inside.end();
  };
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const fs::path name = entry.path().filename();
    const bool ours = ((replaceable.holds && replaceable.holds(name)) || is_output_inside(name)) &&
                      entry.is_regular_file(error);
    if (!ours) {
      const std::string option = replaceable.option.empty() ? "" : replaceable.option + " ";
      throw std::runtime_error(given.string() + " holds " + name.string() + ", not only " +
                               (replaceable.holds ? replaceable.description : "files of this run") +
                               "; not replacing it (remove it or choose another " + option + "folder)");
    }
  }
}

// The flag the signal handler sets (0: no stop asked), read between a run's writes.
volatile std::sig_atomic_t g_stop_signal = 0;

// Atomically swaps two existing paths (Linux renameat2); false if the file system cannot.
bool Exchange(const fs::path& a, const fs::path& b, std::error_code& error) {
  if (FailureInjected("no-exchange")) return false;
  if (::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0) return true;
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP) error = std::error_code(errno, std::generic_category());
  return false;
}

}  // namespace

void CheckOutputFolder(const fs::path& final_path) {
  const fs::path folder = OutputPath(final_path).parent_path();
  const std::string cannot = "cannot write " + final_path.string() + ": ";
  std::error_code error;
  if (!fs::exists(folder, error)) {
    throw std::runtime_error(cannot + "the folder " + ShownFolder(final_path) + " does not exist");
  }
  if (!fs::is_directory(folder, error)) throw std::runtime_error(cannot + ShownFolder(final_path) + " is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    throw std::runtime_error(cannot + "cannot create files in " + ShownFolder(final_path) + " (" +
                             std::strerror(errno) + ")");
  }
}

bool FailureInjected(std::string_view what) {
  for (const char* variable : {"FACERIG_INJECT_FAILURE", "FACERIG_PLAYER_INJECT_FAILURE"}) {
    const char* value = std::getenv(variable);
    for (std::string_view list = value != nullptr ? value : ""; !list.empty();) {
      const std::size_t comma = std::min(list.find(','), list.size());
      if (list.substr(0, comma) == what) return true;
      list.remove_prefix(std::min(comma + 1, list.size()));
    }
  }
  return false;
}

Interrupted::Interrupted(int signal)
    : std::runtime_error(std::string("interrupted by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM")),
      signal_(signal) {}

void InstallStopSignalHandlers() {
  g_stop_signal = 0;
  struct sigaction action {};
  action.sa_handler = [](int signal) { g_stop_signal = signal; };
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

void ThrowIfStopped() {
  if (g_stop_signal != 0) throw Interrupted(g_stop_signal);
}

StopSignalScope::StopSignalScope() {
  sigaction(SIGINT, nullptr, &previous_interrupt_);
  sigaction(SIGTERM, nullptr, &previous_terminate_);
  InstallStopSignalHandlers();
}

StopSignalScope::~StopSignalScope() {
  sigaction(SIGINT, &previous_interrupt_, nullptr);
  sigaction(SIGTERM, &previous_terminate_, nullptr);
}

void CheckAfterWrite(std::string_view step, const fs::path& written) {
  const std::string name(step);
  if (FailureInjected("fail-" + name)) {
    std::error_code ignored;
    fs::remove_all(written, ignored);  // as a writer does when the disk is full
    throw std::runtime_error("cannot write " + written.string() + ": " + std::strerror(ENOSPC));
  }
  if (FailureInjected("term-after-" + name)) ::raise(SIGTERM);
  if (FailureInjected("kill-after-" + name)) ::raise(SIGKILL);
  ThrowIfStopped();
}

OutputSet::~OutputSet() {
  if (!committed_) Abandon();
}

void OutputSet::RemoveStaleTemporaries(const fs::path& folder) {
  if (std::find(cleaned_folders_.begin(), cleaned_folders_.end(), folder) != cleaned_folders_.end()) return;
  cleaned_folders_.push_back(folder);
  std::error_code error;
  for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    if (!IsStale(it->path().filename().string())) continue;
    std::error_code ignored;
    fs::remove_all(it->path(), ignored);  // another run may be removing it too
  }
}

const OutputSet::Entry* OutputSet::FolderHolding(const Entry& entry) const {
  const Entry* holder = nullptr;
  for (const Entry& other : entries_) {
    if (other.final_path == entry.final_path) throw std::runtime_error(entry.given.string() + " is given twice");
    if (other.kind == Kind::kFolder && entry.kind == Kind::kFile && entry.final_path.parent_path() == other.final_path) {
      holder = &other;  // a file directly inside a folder output: written inside its temporary
    } else if (IsInsideFolder(entry.final_path, other.final_path) ||
               IsInsideFolder(other.final_path, entry.final_path)) {
      throw std::runtime_error("the outputs " + other.given.string() + " and " + entry.given.string() +
                               " are inside one another (a file may go directly inside a folder output, no deeper)");
    }
  }
  return holder;
}

fs::path OutputSet::Add(const fs::path& final_path, Kind kind, const ReplaceableFolder& replaceable) {
  Entry entry{OutputPath(final_path), {}, final_path, kind, replaceable};
  if (const Entry* folder_output = FolderHolding(entry)) {
    const fs::path name = entry.final_path.filename();
    const ReplaceableFolder& holds = folder_output->replaceable;
    if (holds.holds && holds.holds(name)) {
      throw std::runtime_error(final_path.string() + " is inside " + (holds.option.empty() ? "" : holds.option + " ") +
                               folder_output->given.string() + " and named like its " + holds.description +
                               "; choose another name");
    }
    entry.temporary = folder_output->temporary / name;
    entry.inside_folder = true;
    entries_.push_back(entry);
    return entry.temporary;
  }
  CheckOutputFolder(final_path);
  const fs::path folder = entry.final_path.parent_path();
  std::error_code error;
  if (kind == Kind::kFolder) {
    CheckReplaceableFolder(entry.final_path, final_path, replaceable);
  } else if (fs::is_directory(entry.final_path, error)) {
    throw std::runtime_error(final_path.string() + " is a folder");
  }
  RemoveStaleTemporaries(folder);
  entry.temporary = folder / TemporaryName("", entry.final_path);
  fs::remove_all(entry.temporary, error);
  if (kind == Kind::kFolder && !fs::create_directory(entry.temporary, error)) {
    throw std::runtime_error("cannot create " + final_path.string() + ": " + error.message());
  }
  entries_.push_back(entry);
  return entry.temporary;
}

// Puts one entry's temporary in place; `placed` says what was done, also when it fails part-way.
std::error_code OutputSet::Place(const Entry& entry, Placed* placed) {
  std::error_code error;
  if (!fs::exists(entry.final_path, error)) {
    fs::rename(entry.temporary, entry.final_path, error);
    if (!error) *placed = Placed::kNew;
  } else if (Exchange(entry.temporary, entry.final_path, error)) {
    *placed = Placed::kExchanged;  // the previous output now has the temporary name
  } else if (!error) {
    // No atomic exchange on this file system: the previous output is set aside for a moment.
    fs::rename(entry.final_path, AsidePath(entry), error);
    if (error) return error;
    *placed = Placed::kAsideOnly;
    fs::rename(entry.temporary, entry.final_path, error);
    if (!error) *placed = Placed::kAside;
  }
  return error;
}

// Undoes Place(): the new output back to its temporary name, the previous one to its place.
std::error_code OutputSet::Unplace(const Entry& entry, Placed placed) {
  std::error_code error;
  switch (placed) {
    case Placed::kNothing: break;
    case Placed::kNew: fs::rename(entry.final_path, entry.temporary, error); break;
    case Placed::kExchanged: Exchange(entry.temporary, entry.final_path, error); break;
    case Placed::kAside: fs::rename(entry.final_path, entry.temporary, error); [[fallthrough]];
    case Placed::kAsideOnly: if (!error) fs::rename(AsidePath(entry), entry.final_path, error); break;
  }
  return error;
}

fs::path OutputSet::AsidePath(const Entry& entry) {
  return entry.temporary.parent_path() / TemporaryName("old-", entry.final_path);
}

void OutputSet::Commit() {
  std::vector<Placed> placed(entries_.size(), Placed::kNothing);
  std::size_t last_placed = 0;  // the "rename" failure injection's
  for (std::size_t i = 0; i < entries_.size(); ++i) last_placed = entries_[i].inside_folder ? last_placed : i;
  std::string failure;
  for (std::size_t i = 0; i < entries_.size() && failure.empty(); ++i) {
    if (entries_[i].inside_folder) continue;  // arrives with its folder
    std::error_code error = FailureInjected("rename") && i == last_placed
                                ? std::make_error_code(std::errc::io_error)
                                : Place(entries_[i], &placed[i]);
    if (error) {
      failure = "cannot rename " + entries_[i].temporary.filename().string() + " to " +
                entries_[i].given.string() + ": " + error.message();
    }
  }
  if (failure.empty()) {
    committed_ = true;
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      std::error_code ignored;  // what is left is removed by the next run
      if (placed[i] == Placed::kExchanged) fs::remove_all(entries_[i].temporary, ignored);
      if (placed[i] == Placed::kAside) fs::remove_all(AsidePath(entries_[i]), ignored);
    }
    return;
  }
  std::string restore_failures;
  for (std::size_t i = entries_.size(); i-- > 0;) {
    if (const std::error_code error = Unplace(entries_[i], placed[i])) {
      restore_failures += "; could not restore " + entries_[i].given.string() + ": " + error.message();
    }
  }
  failure += restore_failures.empty() ? "; the previous outputs are unchanged" : restore_failures;
  Abandon();
  throw std::runtime_error(failure);
}

void OutputSet::Abandon() noexcept {
  for (const Entry& entry : entries_) {
    std::error_code ignored;
    fs::remove_all(entry.temporary, ignored);
  }
}

std::string OutputSet::WithFinalPaths(std::string message) const {
  std::vector<const Entry*> longest_first;
  for (const Entry& entry : entries_) longest_first.push_back(&entry);
  // A temporary folder "…-out" must not match inside a temporary file "…-out.wav".
  std::sort(longest_first.begin(), longest_first.end(), [](const Entry* a, const Entry* b) {
    return a->temporary.native().size() > b->temporary.native().size();
  });
  for (const Entry* entry : longest_first) {
    const std::string& temporary = entry->temporary.native();
    for (std::size_t at = message.find(temporary); at != std::string::npos;
         at = message.find(temporary, at + entry->given.native().size())) {
      message.replace(at, temporary.size(), entry->given.native());
    }
  }
  return message;
}

}  // namespace facerig
