// GLSL 3.30 sources of the face program (FaceRenderer). The fragment shader's
// material numbers are the values of facerig::player::Material.
#pragma once

#include <string>

namespace facerig::player {

// What a fragment shader variant compiles in (bits).
enum ShaderFeature : unsigned {
  kBaseTexture = 1,    // base colour x texture
  kNormalTexture = 2,  // normal map
  kAlphaMask = 4,      // discard below the alpha cutoff
};
inline constexpr unsigned kShaderVariants = 8;

// The shaders with `features` (ShaderFeature bits); UVs are passed only to
// textured variants.
std::string FaceVertexShader(unsigned features);
std::string FaceFragmentShader(unsigned features);

}  // namespace facerig::player
