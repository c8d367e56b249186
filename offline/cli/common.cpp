#include "cli/common.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

#include "facerig/runtime/error.h"
#include "facerig/offline/io/template_cache.h"
#include "facerig/offline/io/template_folder.h"

namespace facerig::cli {

void AddOutputOptions(CLI::App& app, std::string& output, std::string& report_path, const std::string& output_help) {
  app.add_option("-o", output, output_help)->required();
  app.add_option("--json", report_path, "write a JSON report");
}

CLI::Option* AddShapePredictorOption(CLI::App& app, LandmarkParams& params) {
  return app.add_option("--shape-predictor", params.shape_predictor, "dlib 68-point shape predictor file");
}

RawRig LoadMeshForEditing(const std::filesystem::path& path, Units units) {
  TemplateImportOptions options;
  options.units = units;
  RawRig raw = RigBuilder::ToRaw(LoadRigOrTemplateFolder(path, options));
  if (units != Units::kUnknown) raw.units = units;
  return raw;
}

Rig LoadTemplateRig(const std::filesystem::path& path, TemplateImportReport* report) {
  if (!std::filesystem::is_directory(path)) return LoadRigOrTemplateFolder(path);
  TemplateImportOptions options;
  options.cache_folder = DefaultTemplateCacheFolder();
  TemplateImportReport imported;
  Rig rig = ImportTemplateFolder(path, options, &imported);
  switch (imported.cache) {
    case TemplateCacheUse::kRead:
      std::fprintf(stderr, "template %s: read from the cache (%s)\n", path.c_str(), options.cache_folder.c_str());
      break;
    case TemplateCacheUse::kStored:
      std::fprintf(stderr, "template %s: imported, kept in the cache (%s)\n", path.c_str(),
                   options.cache_folder.c_str());
      break;
    case TemplateCacheUse::kNotStored:
      std::fprintf(stderr, "template %s: imported; not kept in the cache: %s\n", path.c_str(),
                   imported.cache_problem.c_str());
      break;
    case TemplateCacheUse::kOff:
      break;
  }
  if (report) *report = imported;
  return rig;
}

void WriteOutputSet(const std::function<void(OutputSet& set)>& write) {
  const StopSignalScope stop_signals;  // SIGINT / SIGTERM: the temporaries go, the previous set stays
  OutputSet set;                        // removes the temporaries unless committed
  try {
    write(set);
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& error) {
    throw std::runtime_error(set.WithFinalPaths(error.what()) + "; the previous outputs are unchanged");
  }
  set.Commit();
}

std::filesystem::path AddOptionalFile(OutputSet& set, const std::string& path) {
  return path.empty() ? std::filesystem::path() : set.Add(path, OutputSet::Kind::kFile);
}

namespace {

// A folder removed with what it holds when the scope ends.
class ScratchFolder {
 public:
  explicit ScratchFolder(std::filesystem::path path) : path_(std::move(path)) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directory(path_);  // in the output's folder, which exists (CheckOutputFolder)
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::string ReplaceAll(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

}  // namespace

std::filesystem::path WriteWithFilesBeside(OutputSet& set, const std::filesystem::path& final_path,
                                           const std::function<void(const std::filesystem::path& path)>& write) {
  namespace fs = std::filesystem;
  CheckOutputFolder(final_path);
  const fs::path folder = fs::absolute(final_path).parent_path();
  // Named as a temporary, so that the next run removes it if this one is killed.
  const ScratchFolder scratch(folder / (std::string(kTemporaryPrefix) + std::to_string(::getpid()) + "-files-" +
                                        final_path.filename().string()));
  try {
    write(scratch.path() / final_path.filename());
  } catch (const std::exception& error) {
    // Name the files where the user asked for them, not in the scratch folder.
    throw std::runtime_error(ReplaceAll(error.what(), scratch.path().string() + "/",
                                        final_path.has_parent_path() ? final_path.parent_path().string() + "/" : ""));
  }
  std::vector<fs::path> made;
  for (const fs::directory_entry& entry : fs::directory_iterator(scratch.path())) made.push_back(entry.path());
  std::sort(made.begin(), made.end());
  fs::path main_temporary;
  for (const fs::path& file : made) {
    const fs::path beside = file.filename() == final_path.filename() ? final_path : folder / file.filename();
    const fs::path temporary = set.Add(beside, OutputSet::Kind::kFile);
    fs::rename(file, temporary);
    if (beside == final_path) main_temporary = temporary;
  }
  if (main_temporary.empty()) {
    throw std::runtime_error("cannot write " + final_path.string() + ": the writer made no such file");
  }
  return main_temporary;
}

void WriteReport(OutputSet& set, const std::string& path, const CommandReport& report) {
  if (path.empty()) return;
  const std::filesystem::path temporary = set.Add(path, OutputSet::Kind::kFile);
  WriteCommandReport(temporary, report);
  CheckAfterWrite("report", temporary);
}

namespace {
thread_local const CommandHooks* g_hooks = nullptr;
}  // namespace

CommandHooksScope::CommandHooksScope(const CommandHooks& hooks) : previous_(g_hooks) { g_hooks = &hooks; }
CommandHooksScope::~CommandHooksScope() { g_hooks = previous_; }

void StageProgress(const char* stage, std::size_t done, std::size_t total) {
  if (g_hooks && g_hooks->progress) g_hooks->progress(stage, done, total);
}

void ProgressBar(const char* label, std::size_t done, std::size_t total) {
  if (g_hooks && g_hooks->progress) return g_hooks->progress(label, done, total);
  static const bool terminal = ::isatty(STDERR_FILENO) == 1;
  if (!terminal) {  // a log file: one line per stage, when it ends
    if (done >= total) std::fprintf(stderr, "%s: %zu/%zu done\n", label, done, total);
    return;
  }
  constexpr int kWidth = 30;
  const int filled = total == 0 ? kWidth : static_cast<int>(kWidth * done / total);
  std::fprintf(stderr, "\r%-14s [%.*s%*s] %zu/%zu", label, filled, "==============================",
               kWidth - filled, "", done, total);
  if (done >= total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

int Fail(const std::exception& error) {
  if (g_hooks && g_hooks->failed) {
    g_hooks->failed(error);
    const auto* stopped = dynamic_cast<const Interrupted*>(&error);
    return stopped ? 128 + stopped->signal() : 1;
  }
  if (const auto* stopped = dynamic_cast<const Interrupted*>(&error)) {
    std::fprintf(stderr, "facerig: %s; nothing written, the previous outputs are unchanged\n", stopped->what());
    return 128 + stopped->signal();
  }
  std::fprintf(stderr, "facerig: %s\n", error.what());
  return 1;
}

int RunWritingCommand(const std::function<int()>& command) {
  try {
    return command();
  } catch (const std::exception& error) {
    return Fail(error);  // SIGINT / SIGTERM too (Interrupted)
  }
}

void CheckWritable(const std::filesystem::path& path) { CheckOutputFolder(path); }

void CheckWritable(std::initializer_list<std::string> paths) {
  for (const std::string& path : paths) {
    if (!path.empty()) CheckWritable(path);
  }
}

}  // namespace facerig::cli
