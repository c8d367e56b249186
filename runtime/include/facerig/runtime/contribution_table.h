// Shape contributions grouped by a small key (a viseme, an emotion): built as
// one list per key, each shape at most once, then frozen into one array with
// offsets, so that a frame walks one contiguous span per key.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace facerig {

template <typename Contribution, std::size_t kKeyCount>
class ContributionTable {
 public:
  class Builder {
   public:
    // Appends `c` to the key's list, or, when the list already has c.shape
    // (e.g. "_L" and "_R" that resolve to one unsided shape), merges it in
    // with merge(existing, c).
    template <typename Merge>
    void Add(std::size_t key, const Contribution& c, Merge merge) {
      for (Contribution& existing : lists_[key]) {
        if (existing.shape == c.shape) {
          merge(existing, c);
          return;
        }
      }
      lists_[key].push_back(c);
    }
    std::vector<Contribution>& list(std::size_t key) { return lists_[key]; }

    ContributionTable Freeze() const {
      ContributionTable table;
      for (std::size_t k = 0; k < kKeyCount; ++k) {
        table.offsets_[k] = static_cast<std::uint32_t>(table.entries_.size());
        table.entries_.insert(table.entries_.end(), lists_[k].begin(), lists_[k].end());
      }
      table.offsets_[kKeyCount] = static_cast<std::uint32_t>(table.entries_.size());
      return table;
    }

   private:
    std::array<std::vector<Contribution>, kKeyCount> lists_;
  };

  // The key's contributions; empty for a key out of range.
  std::span<const Contribution> of(std::size_t key) const {
    if (key >= kKeyCount) return {};
    return std::span<const Contribution>(entries_).subspan(offsets_[key], offsets_[key + 1] - offsets_[key]);
  }
  std::size_t size() const { return entries_.size(); }
  bool empty() const { return entries_.empty(); }

 private:
  std::vector<Contribution> entries_;
  std::array<std::uint32_t, kKeyCount + 1> offsets_{};  // key k: [offsets_[k], offsets_[k + 1])
};

}  // namespace facerig
