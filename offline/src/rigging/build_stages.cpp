#include "facerig/offline/rigging/build_stages.h"

namespace facerig {

double StageSeconds(std::span<const BuildStage> stages, std::string_view name) {
  for (const BuildStage& stage : stages) {
    if (stage.name == name) return stage.seconds;
  }
  return 0.0;
}

double TotalSeconds(std::span<const BuildStage> stages) {
  double total = 0.0;
  for (const BuildStage& stage : stages) total += stage.seconds;
  return total;
}

}  // namespace facerig
