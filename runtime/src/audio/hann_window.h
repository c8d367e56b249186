// The symmetric Hann window every per-frame spectrum of speech uses (the
// alignment features and the audio-only mouth). Private to facerig::runtime.
#pragma once

#include <cstddef>
#include <vector>

namespace facerig::detail {

// 0.5 - 0.5 cos(2 pi i / (size - 1)) for i < size (all zero for size 1).
std::vector<float> HannWindow(std::size_t size);

}  // namespace facerig::detail
