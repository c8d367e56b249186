// A project outside facerig that finds it with find_package(facerig) and
// evaluates one frame of the rig given on the command line.
#include <cstddef>
#include <cstdio>
#include <vector>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/io/rig_file.h"

// Fine under the consumer's -Wall -Wextra -Werror; a warning, so an error,
// if facerig's -Wconversion and -Wshadow reached this file.
int AsInt(std::size_t count) { return count; }

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const facerig::Rig rig = facerig::LoadRig(argv[1]);
  std::vector<float> weights(rig.shape_count(), 0.5f);
  std::vector<glm::vec3> positions(rig.vertex_count());
  const facerig::BlendJob job{&rig, weights, facerig::NormalMode::kNone, positions, {}};
  const facerig::BlendJobError error = job.Run();
  const std::size_t shapes = rig.shape_count();
  const auto as_count = [](std::size_t shapes) { return AsInt(shapes); };
  std::printf("%zu vertices, %d shapes: %s\n", rig.vertex_count(), as_count(shapes), facerig::ToString(error));
  return error == facerig::BlendJobError::kNone ? 0 : 1;
}
