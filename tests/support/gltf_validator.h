// The Khronos glTF validator (tests/runtime/io/gltf_validator, installed with
// `npm ci --prefix tests/runtime/io/gltf_validator`), run from tests.
#pragma once

#include <filesystem>

namespace facerig::test {

// REQUIREs that the validator reports no error on `path` (its report is kept
// next to the file as PATH.validation.txt). FAILs, saying how to install it,
// when the validator is not set up.
void RequireValidatorAccepts(const std::filesystem::path& path);

}  // namespace facerig::test
