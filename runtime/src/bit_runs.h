// Walking sets of vertex or triangle indices kept as bit words (BlendState):
// by maximal runs of consecutive indices, so that the blend copies and
// normalises contiguous memory.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace facerig::bits {

using Words = std::vector<std::uint64_t>;

// f(first, count) for each maximal run of consecutive indices set in `a` or
// `b` and not in `except` (null: none), in increasing order, within words
// [first_word, end_word).
template <typename F>
void ForEachRun(const Words& a, const Words& b, const Words* except, std::size_t first_word, std::size_t end_word,
                F&& f) {
  std::size_t run_start = 0;
  bool in_run = false;
  for (std::size_t w = first_word; w < end_word; ++w) {
    std::uint64_t word = a[w] | b[w];
    if (except != nullptr) word &= ~(*except)[w];
    for (unsigned bit = 0; bit < 64;) {
      if (in_run) {
        const std::uint64_t zeros = ~word >> bit;
        if (zeros == 0) break;  // the run goes on into the next word
        bit += static_cast<unsigned>(std::countr_zero(zeros));
        f(run_start, w * 64 + bit - run_start);
        in_run = false;
      } else {
        const std::uint64_t ones = word >> bit;
        if (ones == 0) break;
        bit += static_cast<unsigned>(std::countr_zero(ones));
        run_start = w * 64 + bit;
        in_run = true;
      }
    }
  }
  if (in_run) f(run_start, end_word * 64 - run_start);
}

template <typename F>
void ForEachRun(const Words& a, const Words& b, const Words* except, F&& f) {
  ForEachRun(a, b, except, 0, a.size(), f);
}

template <typename F>
void ForEachRun(const Words& set, F&& f) {
  ForEachRun(set, set, nullptr, 0, set.size(), f);
}

// f(index) for each index set in `set`, in increasing order.
template <typename F>
void ForEachBit(const Words& set, F&& f) {
  for (std::size_t w = 0; w < set.size(); ++w) {
    for (std::uint64_t word = set[w]; word != 0; word &= word - 1) {
      f(w * 64 + static_cast<std::size_t>(std::countr_zero(word)));
    }
  }
}

inline bool Test(const Words& set, std::size_t index) { return (set[index / 64] >> (index % 64)) & 1u; }

}  // namespace facerig::bits
