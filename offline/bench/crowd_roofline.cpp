#include "bench/crowd_roofline.h"

#include <algorithm>
#include <cstring>

#include "bench/common.h"

double CrowdWork::Bytes() const { return (entries + normal_entries) * (12 + 24) + (moved_vertices + shaded_vertices) * 24; }

CrowdWork CountWork(const facerig::BlendPlan& plan, const std::vector<float>& weights,
                    const facerig::BlendState& state) {
  CrowdWork work;
  for (std::size_t s = 0; s < weights.size(); ++s) {
    if (weights[s] == 0.0f) continue;
    work.active_shapes += 1.0;
    for (const facerig::DeltaRun& run : plan.entry_runs(s)) work.entries += run.count;
    for (const facerig::DeltaRun& run : plan.sum_runs(s)) work.normal_entries += run.count;
    for (const facerig::DeltaRun& run : plan.quadratic_runs(s)) work.normal_entries += run.count;
  }
  const facerig::BlendWork blend = state.LastWork();
  work.moved_vertices = static_cast<double>(blend.moved_vertices);
  work.shaded_vertices = static_cast<double>(blend.shaded_vertices);
  return work;
}

CrowdWork MedianWork(const std::vector<CrowdWork>& work) {
  const auto median = [&](double CrowdWork::*field) {
    std::vector<double> values;
    values.reserve(work.size());
    for (const CrowdWork& w : work) values.push_back(w.*field);
    return UpperMedian(std::move(values));
  };
  CrowdWork m;
  m.active_shapes = median(&CrowdWork::active_shapes);
  m.entries = median(&CrowdWork::entries);
  m.moved_vertices = median(&CrowdWork::moved_vertices);
  m.normal_entries = median(&CrowdWork::normal_entries);
  m.shaded_vertices = median(&CrowdWork::shaded_vertices);
  return m;
}

CrowdRoofline::CrowdRoofline(const CrowdWork& work, std::size_t characters)
    : entries_(static_cast<std::size_t>(work.entries)),
      moved_(static_cast<std::size_t>(work.moved_vertices)),
      normal_entries_(static_cast<std::size_t>(work.normal_entries)),
      shaded_(static_cast<std::size_t>(work.shaded_vertices)),
      deltas_(std::max(entries_, normal_entries_), glm::vec3(0.5f)),
      rest_(std::max(moved_, shaded_), glm::vec3(1.0f)),
      outputs_(characters, std::vector<glm::vec3>(2 * std::max({entries_, normal_entries_, moved_, shaded_}))) {}

void CrowdRoofline::Run(std::size_t character) {
  float* positions = reinterpret_cast<float*>(outputs_[character].data());
  float* normals = positions + outputs_[character].size() / 2 * 3;
  const float* deltas = reinterpret_cast<const float*>(deltas_.data());
  // The restores, then one pass over the deltas per output, like the job.
  std::memcpy(positions, rest_.data(), moved_ * sizeof(glm::vec3));
  for (std::size_t i = 0; i < 3 * entries_; ++i) positions[i] += 0.5f * deltas[i];
  std::memcpy(normals, rest_.data(), shaded_ * sizeof(glm::vec3));
  for (std::size_t i = 0; i < 3 * normal_entries_; ++i) normals[i] += 0.5f * deltas[i];
}

float CrowdRoofline::Checksum() const {
  float sum = 0.0f;
  for (const std::vector<glm::vec3>& out : outputs_) sum += out.front().x + out.back().x;
  return sum;
}
