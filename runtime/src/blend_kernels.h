// The loops both blend paths share, so that they produce the same bits.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "facerig/runtime/rig.h"

namespace facerig::blend {

// positions[v] += w * delta (and normals[v] += w * normal delta unless
// `normals` is null) for every entry of every shape with a non-zero weight,
// in shape order.
inline void AddActiveShapes(const Rig& rig, std::span<const float> weights, glm::vec3* positions,
                            glm::vec3* normals) {
  for (std::size_t s = 0; s < weights.size(); ++s) {
    const float w = weights[s];
    if (w == 0.0f) continue;
    const BlendShapeView shape = rig.shape(s);
    const std::uint32_t* indices = shape.vertex_indices.data();
    const glm::vec3* deltas = shape.position_deltas.data();
    const std::size_t count = shape.vertex_indices.size();
    if (normals != nullptr) {
      // One pass over the entries for both, so each index is read once.
      const glm::vec3* normal_deltas = shape.normal_deltas.data();
      for (std::size_t i = 0; i < count; ++i) {
        positions[indices[i]] += w * deltas[i];
        normals[indices[i]] += w * normal_deltas[i];
      }
    } else {
      for (std::size_t i = 0; i < count; ++i) positions[indices[i]] += w * deltas[i];
    }
  }
}

// kBlendDeltas' renormalisation (a zero sum stays zero).
inline void RenormaliseBlended(glm::vec3& n) {
  const float length_sq = glm::dot(n, n);
  if (length_sq > 0.0f) n *= 1.0f / std::sqrt(length_sq);
}

// ComputeVertexNormals' normalisation of a summed normal.
inline void NormaliseSum(glm::vec3& n) {
  const float length_sq = glm::dot(n, n);
  n = length_sq > 0.0f ? n / std::sqrt(length_sq) : glm::vec3(0.0f, 0.0f, 1.0f);
}

// NormaliseSum over `count` consecutive vectors: four at a time with SSE2
// (the same operations in each lane, so the same bits), the rest one by one.
inline void NormaliseSums(glm::vec3* n, std::size_t count) {
  std::size_t i = 0;
#if defined(__SSE2__)
  const __m128 zero = _mm_setzero_ps();
  for (; i + 4 <= count; i += 4) {
    // Four vectors in three registers: a = x0 y0 z0 x1, b = y1 z1 x2 y2, c = z2 x3 y3 z3.
    float* p = reinterpret_cast<float*>(n + i);
    const __m128 a = _mm_loadu_ps(p), b = _mm_loadu_ps(p + 4), c = _mm_loadu_ps(p + 8);
    const __m128 x = _mm_shuffle_ps(a, _mm_shuffle_ps(b, c, _MM_SHUFFLE(1, 1, 2, 2)), _MM_SHUFFLE(2, 0, 3, 0));
    const __m128 y = _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1)),
                                    _mm_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3)), _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 z = _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2)),
                                    _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0)), _MM_SHUFFLE(2, 0, 2, 0));
    // glm::dot's order: (x * x + y * y) + z * z.
    const __m128 length_sq = _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, x), _mm_mul_ps(y, y)), _mm_mul_ps(z, z));
    if (_mm_movemask_ps(_mm_cmpgt_ps(length_sq, zero)) != 0xF) {  // a zero or non-finite sum
      for (std::size_t k = i; k < i + 4; ++k) NormaliseSum(n[k]);
      continue;
    }
    const __m128 length = _mm_sqrt_ps(length_sq);
    _mm_storeu_ps(p, _mm_div_ps(a, _mm_shuffle_ps(length, length, _MM_SHUFFLE(1, 0, 0, 0))));
    _mm_storeu_ps(p + 4, _mm_div_ps(b, _mm_shuffle_ps(length, length, _MM_SHUFFLE(2, 2, 1, 1))));
    _mm_storeu_ps(p + 8, _mm_div_ps(c, _mm_shuffle_ps(length, length, _MM_SHUFFLE(3, 3, 3, 2))));
  }
#endif
  for (; i < count; ++i) NormaliseSum(n[i]);
}

// out[k] += w * deltas[k] for k < count, as floats: the same operations as
// per vector, four floats at a time (SSE2, no overlap between the arrays).
inline void AddRun(glm::vec3* out, const glm::vec3* deltas, std::size_t count, float w) {
  float* to = reinterpret_cast<float*>(out);
  const float* from = reinterpret_cast<const float*>(deltas);
  const std::size_t floats = 3 * count;
  std::size_t i = 0;
#if defined(__SSE2__)
  const __m128 weight = _mm_set1_ps(w);
  for (; i + 8 <= floats; i += 8) {
    const __m128 a = _mm_add_ps(_mm_loadu_ps(to + i), _mm_mul_ps(weight, _mm_loadu_ps(from + i)));
    const __m128 b = _mm_add_ps(_mm_loadu_ps(to + i + 4), _mm_mul_ps(weight, _mm_loadu_ps(from + i + 4)));
    _mm_storeu_ps(to + i, a);
    _mm_storeu_ps(to + i + 4, b);
  }
#endif
  for (; i < floats; ++i) to[i] += w * from[i];
}

// ComputeVertexNormals' triangle normal: twice the area, so area-weighted.
inline glm::vec3 TriangleNormal(const glm::vec3* positions, const Triangle& t) {
  return glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
}

}  // namespace facerig::blend
