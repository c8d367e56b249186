// facerig-bench crowd: how far the blended recomputed normals (the crowd's
// kBlendRecomputedDeltas) are from kRecompute's, where the surface is smooth.
#pragma once

#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

class NormalAccuracy {
 public:
  explicit NormalAccuracy(const facerig::Rig& rig);
  // One character-frame: its blended normals against kRecompute's for its weights.
  void Add(std::span<const float> weights, std::span<const glm::vec3> blended_normals);

  double worst_smooth_degrees() const { return worst_smooth_; }
  double worst_degrees() const { return worst_; }
  // The share of the vertices counted as smooth: no triangle of theirs more
  // than 30 degrees off their recomputed normal.
  double smooth_share() const;
  std::size_t samples() const { return samples_; }

 private:
  const facerig::Rig& rig_;
  std::vector<glm::vec3> positions_, normals_;
  std::vector<float> crease_cosine_;  // per vertex: the smallest cosine to its triangles' normals
  double worst_smooth_ = 0.0, worst_ = 0.0;
  std::size_t samples_ = 0, smooth_samples_ = 0;
};
