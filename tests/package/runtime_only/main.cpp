// facerig::runtime alone (no tinygltf, no nlohmann_json): reads the .frig rig
// given on the command line and evaluates one frame.
#include <cstdio>
#include <vector>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/files/frig.h"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const facerig::Rig rig = facerig::ReadFrig(argv[1]);
  std::vector<float> weights(rig.shape_count(), 0.5f);
  std::vector<glm::vec3> positions(rig.vertex_count());
  const facerig::BlendJob job{&rig, weights, facerig::NormalMode::kNone, positions, {}};
  const facerig::BlendJobError error = job.Run();
  std::printf("runtime only: %zu vertices, %zu shapes: %s\n", rig.vertex_count(), rig.shape_count(),
              facerig::ToString(error));
  return error == facerig::BlendJobError::kNone ? 0 : 1;
}
