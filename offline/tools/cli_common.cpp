#include "cli_common.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/atomic_file.h"
#include "facerig/offline/io/template_folder.h"

namespace facerig::cli {

RawRig LoadMeshForEditing(const std::filesystem::path& path, Units units) {
  TemplateImportOptions options;
  options.units = units;
  RawRig raw = RigBuilder::ToRaw(LoadRigOrTemplateFolder(path, options));
  if (units != Units::kUnknown) raw.units = units;
  return raw;
}

void WriteJsonAtomically(const std::filesystem::path& path, const nlohmann::json& json) {
  WriteFileAtomically(path, json.dump(2) + "\n");
}

void ProgressBar(const char* label, std::size_t done, std::size_t total) {
  constexpr int kWidth = 30;
  const int filled = total == 0 ? kWidth : static_cast<int>(kWidth * done / total);
  std::fprintf(stderr, "\r%-14s [%.*s%*s] %zu/%zu", label, filled, "==============================",
               kWidth - filled, "", done, total);
  if (done >= total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

int Fail(const std::exception& error) {
  std::fprintf(stderr, "facerig: %s\n", error.what());
  return 1;
}

int RunWritingCommand(const std::function<int()>& command) {
  try {
    return command();
  } catch (const Interrupted& stopped) {
    std::fprintf(stderr, "facerig: %s; nothing written, the previous outputs are unchanged\n", stopped.what());
    return 128 + stopped.signal();
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

void WriteOutputSet(const std::function<void(OutputSet&)>& write) {
  const StopSignalScope stop_signals;
  OutputSet set;  // removes the temporaries unless committed
  try {
    write(set);
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& error) {
    throw std::runtime_error(set.WithFinalPaths(error.what()) + "; the previous outputs are unchanged");
  }
  set.Commit();
}

void CheckWritable(const std::filesystem::path& path) {
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const std::filesystem::path probe = folder / (".facerig-write-check-" + path.filename().string());
  {
    std::ofstream out(probe, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw IoError(IoErrorKind::kWriteFailed, path.string(),
                    "cannot create files in '" + folder.string() + "' (missing folder or no permission)");
    }
  }
  std::error_code ignored;
  std::filesystem::remove(probe, ignored);
}

}  // namespace facerig::cli
