// A project outside facerig that finds it with find_package(facerig) and
// evaluates one frame of the rig given on the command line.
#include <cstdio>
#include <vector>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/io/rig_file.h"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const facerig::Rig rig = facerig::LoadRig(argv[1]);
  std::vector<float> weights(rig.shape_count(), 0.5f);
  std::vector<glm::vec3> positions(rig.vertex_count());
  const facerig::BlendJob job{&rig, weights, facerig::NormalMode::kNone, positions, {}};
  const facerig::BlendJobError error = job.Run();
  std::printf("%zu vertices, %zu shapes: %s\n", rig.vertex_count(), rig.shape_count(),
              facerig::ToString(error));
  return error == facerig::BlendJobError::kNone ? 0 : 1;
}
