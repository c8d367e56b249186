// The built-in head's proportions lie in the range of real faces (issue 34):
// measured as `facerig-bench proportions` does (measure/face_proportions.h),
// against ICT-FaceKit's random identities, on other seeds than the bench's.
#include <cmath>
#include <cstdio>

#include <catch2/catch.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/runtime/mesh.h"
#include "measure/face_proportions.h"
#include "support/default_head_poses.h"
#include "support/ict_faces.h"

namespace facerig {

TEST_CASE("(shared data) Default head: nose, eyes, mouth, lower face and face width within 2 SD of ICT-FaceKit's "
          "random identities",
          "[default_head][shared-data][accuracy]") {
  LandmarkDetector detector;
  const test::FaceProportions head = test::MeasureFaceProportions(detector, NeutralMesh(test::DefaultHead()));
  CHECK(head.eyes_fitted == 2);  // the eye points on the lid margins, as on the ICT faces
  const test::ProportionReference ict = test::IctProportionReference(detector, test::IctFaces(), 60, 101);
  for (test::Proportion which : test::kProportions) {
    const auto i = static_cast<std::size_t>(which);
    const double z = ict.ZScore(which, head[which]);
    std::printf("default head %-12s %.4f; ICT-FaceKit %.4f +- %.4f: z %+.2f\n", test::ProportionName(which),
                head[which], ict.mean[i], ict.sd[i], z);
    INFO(test::ProportionName(which) << ": " << head[which] << " against " << ict.mean[i] << " +- " << ict.sd[i]);
    CHECK(ict.sd[i] > 0.0);
    // Before issue 34 the nose was 6-19 SD out (longer and narrower), the
    // lower face shorter and the eyes taller than any of these faces.
    CHECK(std::abs(z) <= 2.0);
  }
}

}  // namespace facerig
