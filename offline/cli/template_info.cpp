#include "cli/template_info.h"

#include <cstdio>
#include <string>

namespace facerig {

void PrintTemplateInfo(const FaceTemplateInfo& info) {
  std::string derived;
  for (const std::string& field : info.derived) derived += (derived.empty() ? "" : ", ") + field;
  std::fprintf(stderr, "template descriptor '%s': %s%s%s%s%s\n", info.name.c_str(), ToString(info.source),
               info.source_path.empty() ? "" : " ", info.source_path.c_str(), derived.empty() ? "" : "; derived: ",
               derived.c_str());
}

nlohmann::json TemplateInfoReport(const FaceTemplateInfo& info) {
  return {{"name", info.name},
          {"source", ToString(info.source)},
          {"path", info.source_path},
          {"derived", info.derived},
          {"region_vertices", info.region.count()}};
}

}  // namespace facerig
