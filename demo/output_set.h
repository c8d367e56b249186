// The headless player's outputs (frames folder, WAV, MP4, timing JSON) as one
// set: facerig::OutputSet (facerig/runtime/io/output_set.h), shared with the
// command-line tools.
#pragma once

#include "facerig/runtime/io/output_set.h"

namespace facerig::player {

using facerig::FailureInjected;
using facerig::kTemporaryPrefix;
using facerig::OutputSet;

}  // namespace facerig::player
