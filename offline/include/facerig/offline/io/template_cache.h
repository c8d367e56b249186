// A template folder's import kept on disk between runs: reading ICT-FaceKit's
// 54 OBJs takes about a second, its imported rig as a .frig a twentieth.
// An entry is named by a hash (XXH3, 128 bits) of everything the import's
// result depends on: the code (the library file this is compiled into), the
// import options, and every file under the folder (relative path, size,
// bytes). A changed, added or removed file, other options or a rebuilt
// library give another name, so a stale entry is never read; entries are not
// removed (about 13 MB for ICT-FaceKit): delete the folder to free them.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// $FACERIG_CACHE_DIR, else $XDG_CACHE_HOME/facerig, else $HOME/.cache/facerig;
// empty when FACERIG_CACHE_DIR is "off" or none of them is set.
std::filesystem::path DefaultTemplateCacheFolder();

// The entry name of `folder` imported with `options` (32 hex digits); nullopt
// when a file cannot be read (the import then reports it).
std::optional<std::string> TemplateCacheKey(const std::filesystem::path& folder,
                                            const TemplateImportOptions& options);

// The entry `key` under `cache_folder` and its import report (neutral_path
// under `folder`); nullopt when there is none or it cannot be read.
std::optional<Rig> ReadCachedTemplate(const std::filesystem::path& cache_folder, const std::string& key,
                                      const std::filesystem::path& folder, TemplateImportReport* report);

// Writes the entry as one folder, renamed into place at the end.
// \throw std::runtime_error or IoError when it cannot be written.
void StoreCachedTemplate(const std::filesystem::path& cache_folder, const std::string& key,
                         const std::filesystem::path& folder, const Rig& rig, const TemplateImportReport& report);

}  // namespace facerig
