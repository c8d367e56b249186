#include "bench/crowd_roofline.h"

#include <algorithm>

#include "bench/common.h"

double CrowdWork::Bytes() const { return (entries + normal_entries) * 12 + (moved_vertices + shaded_vertices) * 24; }

CrowdWork CountWork(const facerig::BlendPlan& plan, const std::vector<float>& weights,
                    const facerig::BlendState& state) {
  CrowdWork work;
  const auto count = [](std::span<const facerig::DeltaRun> runs) {
    double n = 0.0;
    for (const facerig::DeltaRun& run : runs) n += run.count;
    return n;
  };
  for (std::size_t s = 0; s < weights.size(); ++s) {
    if (weights[s] == 0.0f) continue;
    work.active_shapes += 1.0;
    work.entries += count(plan.entry_runs(s));
    work.normal_entries += count(plan.sum_runs(s)) + count(plan.quadratic_runs(s));
    for (std::size_t t = s + 1; t < weights.size(); ++t) {
      if (weights[t] != 0.0f) work.normal_entries += count(plan.pair_runs(s, t));
    }
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
    : deltas_(static_cast<std::size_t>(work.entries + work.normal_entries), glm::vec3(0.5f)),
      rest_(static_cast<std::size_t>(work.moved_vertices + work.shaded_vertices), glm::vec3(1.0f)),
      outputs_(characters, std::vector<glm::vec3>(rest_.size())) {}

void CrowdRoofline::Run(std::size_t character) {
  // Four sums, so that the reads need not wait on one another.
  const float* deltas = reinterpret_cast<const float*>(deltas_.data());
  const std::size_t floats = 3 * deltas_.size();
  float sums[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  std::size_t i = 0;
  for (; i + 4 <= floats; i += 4) {
    for (std::size_t k = 0; k < 4; ++k) sums[k] += deltas[i + k];
  }
  for (; i < floats; ++i) sums[0] += deltas[i];
  const float offset = 1e-9f * (sums[0] + sums[1] + sums[2] + sums[3]);
  const float* rest = reinterpret_cast<const float*>(rest_.data());
  float* out = reinterpret_cast<float*>(outputs_[character].data());
  for (std::size_t k = 0; k < 3 * rest_.size(); ++k) out[k] = rest[k] + offset;
}

float CrowdRoofline::Checksum() const {
  float sum = 0.0f;
  for (const std::vector<glm::vec3>& out : outputs_) sum += out.front().x + out.back().x;
  return sum;
}
