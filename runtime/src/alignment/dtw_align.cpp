#include "facerig/runtime/alignment/dtw_align.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace facerig {
namespace {

enum class DtwStep : std::uint8_t { kDiagonal, kFromAbove, kFromLeft };

float Distance(std::span<const float> a, std::span<const float> b) {
  float sum = 0.0f;
  for (std::size_t k = 0; k < a.size(); ++k) sum += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(sum);
}

void CheckInputs(const AudioFeatures& rows, const AudioFeatures& columns, const DtwBand& band, std::size_t max_cells) {
  const std::size_t n = rows.frame_count(), m = columns.frame_count();
  if (n == 0 || m == 0) throw AlignmentError("cannot align an empty feature sequence");
  if (rows.dimension != columns.dimension) throw AlignmentError("feature sequences of different dimensions");
  bool valid = band.first.size() == n && band.last.size() == n && band.first[0] == 0 && band.last[n - 1] == m - 1;
  for (std::size_t i = 0; valid && i < n; ++i) {
    valid = band.first[i] <= band.last[i] && band.last[i] < m &&
            (i == 0 || (band.first[i] >= band.first[i - 1] && band.last[i] >= band.last[i - 1] &&
                        band.first[i] <= band.last[i - 1] + 1));
  }
  if (!valid) throw AlignmentError("the warping band does not fit the feature sequences");
  if (band.cell_count() > max_cells) {
    throw AlignmentError("aligning " + std::to_string(n) + " x " + std::to_string(m) + " frames needs " +
                         std::to_string(band.cell_count()) + " cells, more than the limit of " +
                         std::to_string(max_cells) + "; split the audio into shorter lines");
  }
}

// Walks the recorded steps back from the last cell.
DtwPath TracePath(const DtwBand& band, const std::vector<std::size_t>& row_offset, const std::vector<DtwStep>& steps) {
  const std::size_t n = band.first.size();
  DtwPath path;
  path.first_column.assign(n, 0);
  path.last_column.assign(n, 0);
  std::size_t i = n - 1, j = band.last[n - 1];
  path.last_column[i] = j;
  for (;;) {
    path.first_column[i] = j;
    if (i == 0 && j == 0) break;
    const DtwStep step = steps[row_offset[i] + (j - band.first[i])];
    if (step == DtwStep::kFromLeft) {
      --j;
      continue;
    }
    --i;
    if (step == DtwStep::kDiagonal) --j;
    path.last_column[i] = j;
  }
  return path;
}

// The mean distance of the path's cells outside pauses (0 when it has none).
double MeanPathDistance(const DtwPath& path, const AudioFeatures& rows, const AudioFeatures& columns,
                        const DtwPauseColumns* pauses) {
  double sum = 0.0;
  std::size_t cells = 0;
  for (std::size_t i = 0; i < path.first_column.size(); ++i) {
    for (std::size_t j = path.first_column[i]; j <= path.last_column[i]; ++j) {
      if (pauses && pauses->quiet[j]) continue;
      sum += Distance(rows.frame(i), columns.frame(j));
      ++cells;
    }
  }
  return cells > 0 ? sum / static_cast<double>(cells) : 0.0;
}

}  // namespace

std::size_t DtwBand::cell_count() const {
  std::size_t cells = 0;
  for (std::size_t i = 0; i < first.size(); ++i) cells += last[i] - first[i] + 1;
  return cells;
}

DtwBand MakeDtwBand(std::span<const double> centre, std::size_t columns, std::size_t radius) {
  DtwBand band;
  if (centre.empty() || columns == 0) return band;
  const std::size_t n = centre.size();
  band.first.resize(n);
  band.last.resize(n);
  const auto max_column = static_cast<double>(columns - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const double c = std::clamp(centre[i], 0.0, max_column);
    std::size_t first = static_cast<std::size_t>(std::max(0.0, std::floor(c) - static_cast<double>(radius)));
    std::size_t last = static_cast<std::size_t>(std::min(max_column, std::ceil(c) + static_cast<double>(radius)));
    if (i == 0) first = 0;
    if (i > 0) {
      first = std::max(first, band.first[i - 1]);
      first = std::min(first, band.last[i - 1] + 1);
      last = std::max({last, band.last[i - 1], first});
    }
    band.first[i] = first;
    band.last[i] = std::min(last, columns - 1);
  }
  band.last[n - 1] = columns - 1;
  return band;
}

DtwPath AlignFeatureSequences(const AudioFeatures& rows, const AudioFeatures& columns, const DtwBand& band,
                              std::size_t max_cells, const DtwPauseColumns* pauses) {
  CheckInputs(rows, columns, band, max_cells);
  if (pauses && (pauses->quiet.size() != columns.frame_count() ||
                 (!pauses->quiet_rows.empty() && pauses->quiet_rows.size() != rows.frame_count()))) {
    throw AlignmentError("the pause flags do not match the recording's frames");
  }
  const std::size_t n = rows.frame_count();
  std::vector<std::size_t> row_offset(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) row_offset[i + 1] = row_offset[i] + band.last[i] - band.first[i] + 1;
  std::vector<DtwStep> steps(row_offset[n]);
  constexpr double kUnreachable = std::numeric_limits<double>::infinity();
  std::vector<double> previous, current;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t first = band.first[i], width = band.last[i] - first + 1;
    current.assign(width, kUnreachable);
    const auto above = [&](std::size_t j) {  // accumulated cost of (i - 1, j)
      return i > 0 && j >= band.first[i - 1] && j <= band.last[i - 1] ? previous[j - band.first[i - 1]] : kUnreachable;
    };
    for (std::size_t k = 0; k < width; ++k) {
      const std::size_t j = first + k;
      const double d = !pauses || !pauses->quiet[j] ? Distance(rows.frame(i), columns.frame(j))
                       : !pauses->quiet_rows.empty() && pauses->quiet_rows[i] ? 0.0
                                                                              : pauses->cost;
      if (i == 0 && j == 0) {
        current[k] = d;
        continue;
      }
      const double diagonal = j > 0 ? above(j - 1) + 2.0 * d : kUnreachable;
      const double vertical = above(j) + d;
      const double horizontal = k > 0 ? current[k - 1] + d : kUnreachable;
      DtwStep step = DtwStep::kDiagonal;
      double best = diagonal;
      if (vertical < best) step = DtwStep::kFromAbove, best = vertical;
      if (horizontal < best) step = DtwStep::kFromLeft, best = horizontal;
      current[k] = best;
      steps[row_offset[i] + k] = step;
    }
    std::swap(previous, current);
  }
  DtwPath path = TracePath(band, row_offset, steps);
  path.cost = previous.back() / static_cast<double>(n + columns.frame_count());
  path.mean_distance = MeanPathDistance(path, rows, columns, pauses);
  return path;
}

}  // namespace facerig
