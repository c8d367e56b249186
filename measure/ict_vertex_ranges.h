// ICT-FaceKit's vertex ranges (README.upstream.md), for the tests and benches
// that measure a region of its rigs. Its parts are stored in this order: the
// face, head and neck, mouth socket, eye sockets, gums and tongue, teeth,
// eyeballs, then overlays that intersect the eyes by design (lacrimal fluid,
// eye blend and occlusion meshes, eyelashes).
#pragma once

#include <cstdint>

namespace facerig::test::ict {

// Vertices [begin, end).
struct VertexRange {
  std::uint32_t begin;
  std::uint32_t end;

  constexpr bool Contains(std::uint32_t v) const { return v >= begin && v < end; }
};

// The face: where expression errors are measured.
inline constexpr VertexRange kFace{0, 9409};
// The face, head and neck.
inline constexpr VertexRange kSkin{0, 11248};
// Everything before the teeth: the eyelid margins lie in the eye sockets.
inline constexpr VertexRange kBeforeTeeth{0, 17039};
inline constexpr VertexRange kGumsAndTongue{14062, 17039};
inline constexpr VertexRange kTeeth{17039, 21451};
// Everything but the overlays.
inline constexpr VertexRange kSolid{0, 24591};

}  // namespace facerig::test::ict
