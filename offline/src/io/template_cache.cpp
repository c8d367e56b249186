#include "facerig/offline/io/template_cache.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>
#include <xxhash.h>

#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/io/rig_file.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

constexpr const char* kCacheRigFile = "rig.frig";
constexpr const char* kCacheReportFile = "import.json";

class ContentHasher {
 public:
  ContentHasher() : state_(XXH3_createState(), XXH3_freeState) { XXH3_128bits_reset(state_.get()); }

  void Add(const void* data, std::size_t size) { XXH3_128bits_update(state_.get(), data, size); }
  void Add(const std::string& text) {
    const std::uint64_t size = text.size();
    Add(&size, sizeof size);  // so that ("ab", "c") and ("a", "bc") differ
    Add(text.data(), text.size());
  }
  // The file's bytes; false when it cannot be read.
  bool AddFile(const fs::path& path) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!file) return false;
    std::vector<char> buffer(1 << 20);
    while (const std::size_t got = std::fread(buffer.data(), 1, buffer.size(), file.get())) Add(buffer.data(), got);
    return std::ferror(file.get()) == 0;
  }
  std::string Hex() {
    const XXH128_hash_t hash = XXH3_128bits_digest(state_.get());
    char text[33];
    std::snprintf(text, sizeof text, "%016llx%016llx", static_cast<unsigned long long>(hash.high64),
                  static_cast<unsigned long long>(hash.low64));
    return text;
  }

 private:
  std::unique_ptr<XXH3_state_t, XXH_errorcode (*)(XXH3_state_t*)> state_;
};

// The file holding this code: the shared library, or the program it is linked into.
fs::path CodeFile() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&DefaultTemplateCacheFolder), &info) != 0 && info.dli_fname != nullptr) {
    std::error_code error;
    if (fs::is_regular_file(info.dli_fname, error)) return info.dli_fname;
  }
  return "/proc/self/exe";
}

std::string OptionsText(const TemplateImportOptions& options) {
  nlohmann::json json = {{"neutral_file", options.neutral_file}, {"shape_names", options.shape_names},
                         {"glob", options.glob}, {"relative_drop_threshold", options.relative_drop_threshold},
                         {"with_normal_deltas", options.with_normal_deltas},
                         {"units", static_cast<int>(options.units)}, {"up_axis", static_cast<int>(options.up_axis)}};
  return json.dump();
}

// Every regular file under `folder`, by relative path, in a fixed order.
std::vector<fs::path> FilesUnder(const fs::path& folder, std::error_code& error) {
  std::vector<fs::path> files;
  for (fs::recursive_directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    if (it->is_regular_file(error)) files.push_back(fs::relative(it->path(), folder, error));
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

fs::path DefaultTemplateCacheFolder() {
  if (const char* named = std::getenv("FACERIG_CACHE_DIR")) {
    return std::string(named) == "off" ? fs::path() : fs::path(named);
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
    return fs::path(xdg) / "facerig";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    return fs::path(home) / ".cache" / "facerig";
  }
  return {};
}

std::optional<std::string> TemplateCacheKey(const fs::path& folder, const TemplateImportOptions& options) {
  ContentHasher hasher;
  hasher.Add(std::string("facerig template cache 1"));
  if (!hasher.AddFile(CodeFile())) return std::nullopt;
  hasher.Add(OptionsText(options));
  std::error_code error;
  const std::vector<fs::path> files = FilesUnder(folder, error);
  if (error) return std::nullopt;
  for (const fs::path& file : files) {
    hasher.Add(file.generic_string());
    const std::uint64_t size = fs::file_size(folder / file, error);
    if (error) return std::nullopt;
    hasher.Add(&size, sizeof size);
    if (!hasher.AddFile(folder / file)) return std::nullopt;
  }
  return hasher.Hex();
}

std::optional<Rig> ReadCachedTemplate(const fs::path& cache_folder, const std::string& key, const fs::path& folder,
                                      TemplateImportReport* report) {
  const fs::path entry = cache_folder / key;
  std::error_code error;
  if (!fs::is_regular_file(entry / kCacheRigFile, error) || !fs::is_regular_file(entry / kCacheReportFile, error)) {
    return std::nullopt;
  }
  try {
    const nlohmann::json json = nlohmann::json::parse(std::ifstream(entry / kCacheReportFile));
    Rig rig = LoadRig(entry / kCacheRigFile);
    if (report) {
      report->neutral_path = (folder / json.at("neutral_file").get<std::string>()).string();
      report->drop_threshold = json.at("drop_threshold").get<float>();
      report->kept_entries = json.at("kept_entries").get<std::size_t>();
      report->dropped_entries = json.at("dropped_entries").get<std::size_t>();
      report->largest_dropped = json.at("largest_dropped").get<float>();
      report->units = rig.units();
      report->units_guessed = json.at("units_guessed").get<bool>();
      report->uv_seam_vertices = json.at("uv_seam_vertices").get<std::size_t>();
    }
    return rig;
  } catch (const std::exception&) {
    return std::nullopt;  // a damaged entry is imported again and replaced
  }
}

void StoreCachedTemplate(const fs::path& cache_folder, const std::string& key, const fs::path& folder,
                         const Rig& rig, const TemplateImportReport& report) {
  fs::create_directories(cache_folder);
  const fs::path neutral_file = fs::path(report.neutral_path).lexically_relative(folder);
  const nlohmann::json json = {{"neutral_file", neutral_file.generic_string()},
                               {"drop_threshold", report.drop_threshold},
                               {"kept_entries", report.kept_entries},
                               {"dropped_entries", report.dropped_entries},
                               {"largest_dropped", report.largest_dropped},
                               {"units_guessed", report.units_guessed},
                               {"uv_seam_vertices", report.uv_seam_vertices}};
  OutputSet set;
  // A damaged entry (ReadCachedTemplate refused it) is replaced.
  const ReplaceableFolder entry_files{
      .holds = [](const fs::path& name) { return name == kCacheRigFile || name == kCacheReportFile; },
      .description = "a template cache entry",
      .option = "FACERIG_CACHE_DIR"};
  const fs::path entry = set.Add(cache_folder / key, OutputSet::Kind::kFolder, entry_files);
  SaveRig(entry / kCacheRigFile, rig);
  std::ofstream file(entry / kCacheReportFile);
  file << json.dump(1) << "\n";
  file.close();
  if (!file) throw std::runtime_error("could not write " + (cache_folder / key / kCacheReportFile).string());
  set.Commit();
}

}  // namespace facerig
