// Small meshes and shared fixtures for the tests.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"
#include "facerig/runtime/speech/phoneme.h"
#include "facerig/runtime/speech/viseme.h"

namespace facerig::test {

// A shape's position delta at every vertex of the rig (zero where the sparse shape has none).
std::vector<glm::vec3> DenseDeltas(const Rig& rig, std::size_t shape);

// An n x n vertex grid in the XY plane (unit spacing), two parts ("left",
// "right" halves of the triangles), UVs, and `shape_count` sparse shapes, each
// moving a different subset of vertices (deterministic). With normal deltas
// when `with_normal_deltas`.
// A mesh of positions and triangles only (the tests' small hand-made meshes).
Mesh MeshOf(std::span<const glm::vec3> positions, std::span<const Triangle> triangles);

// A closed UV sphere: rings + 1 rows (pole rows included) of `segments`
// vertices, vertex (r, s) at point(theta, phi) with theta = pi r / rings and
// phi = 2 pi s / segments (a unit sphere: sin(theta) cos(phi), cos(theta),
// sin(theta) sin(phi)). Replaces positions and triangles.
void MakeUvSphere(int rings, int segments, const std::function<glm::vec3(double theta, double phi)>& point,
                  std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles);

RawRig MakeGridRawRig(int n, int shape_count, bool with_normal_deltas = false);
Rig MakeGridRig(int n, int shape_count, bool with_normal_deltas = false);
// A viseme key from times in seconds.
inline VisemeKey Key(double start, double end, Viseme viseme, float strength = 1.0f) {
  return {Seconds(start), Seconds(end), viseme, strength};
}
// A phoneme from times in seconds (espeak-ng's phoneme names).
inline Phoneme MakePhoneme(double start, double duration, std::string_view symbol,
                           std::string_view language = "en-us", bool word_start = false) {
  Phoneme phoneme;
  phoneme.start = Seconds(start);
  phoneme.duration = Seconds(duration);
  phoneme.symbol.assign(symbol);
  phoneme.language.assign(language);
  phoneme.word_start = word_start;
  return phoneme;
}

// A grid rig (n x n) with one shape per name, named so, for the name-matching tests.
Rig MakeNamedGridRig(const std::vector<std::string>& names, int n = 6);

// ../shared/data/ict-facekit (compile-time path).
std::filesystem::path IctDir();
// The ICT-FaceKit rig (53 shapes), imported once and cached as a .frig in the
// test output folder for the other test processes of the same build.
const Rig& IctRig();

// A fresh path under the build's test output folder.
std::filesystem::path OutputPath(const std::string& file_name);
// An empty folder of that name under the test output folder (emptied if it exists).
std::filesystem::path FreshOutputFolder(const std::string& name);

// True when two rigs have the same topology, parts, names, units and deltas
// (positions and deltas within `tolerance`).
bool RigsEqual(const Rig& a, const Rig& b, float tolerance, std::string* difference = nullptr);

}  // namespace facerig::test
