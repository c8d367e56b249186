// GLSL 3.30 sources of the face program (FaceRenderer). The fragment shader's
// material numbers are the values of facerig::player::Material.
#pragma once

namespace facerig::player {

extern const char* const kFaceVertexShader;
extern const char* const kFaceFragmentShader;

}  // namespace facerig::player
