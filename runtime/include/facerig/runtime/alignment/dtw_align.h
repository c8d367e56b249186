// Dynamic time warping of two feature sequences inside a band, in
// O(rows x band) time and bytes: what aligns a synthetic rendition of a
// transcript with its recording (phoneme_alignment.h).
#pragma once

#include <cstddef>
#include <span>
#include <stdexcept>
#include <vector>

#include "facerig/runtime/audio/features.h"

namespace facerig {

// Alignment input that cannot be aligned: mismatched features, or a problem
// too large for the cell budget.
class AlignmentError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The columns row i may use: [first[i], last[i]], non-decreasing in i,
// first[0] == 0, last.back() == columns - 1, and each row overlapping the
// previous one's reach (first[i] <= last[i-1] + 1).
struct DtwBand {
  std::vector<std::size_t> first, last;
  std::size_t cell_count() const;
};

// The band of half-width `radius` around `centre` (one column per row,
// fractional), widened where needed to keep the rows connected.
DtwBand MakeDtwBand(std::span<const double> centre, std::size_t columns, std::size_t radius);

// For each row: the first and last column the warping path visits there.
struct DtwPath {
  std::vector<std::size_t> first_column, last_column;
  double cost = 0.0;  // accumulated distance, divided by rows + columns
  // The mean distance of the cells the path visits outside pauses (each
  // once, unweighted): how alike the matched frames are.
  double mean_distance = 0.0;
};

// Columns (the recording's frames) inside pauses: each costs `cost` on a
// row of speech instead of its distance, and nothing on a quiet row (the
// reference's own silence, whatever the two noise floors), so the path
// crosses a pause on the reference's nearest silence, or on one row, without
// matching it to the rows' speech; it climbs through speech rows there only
// at that price (no cheaper than unrelated frames).
struct DtwPauseColumns {
  std::vector<bool> quiet;       // one per column
  std::vector<bool> quiet_rows;  // one per row (empty: none quiet)
  double cost = 0.0;
};

// Warps `rows` onto `columns` (same dimension) with the symmetric step
// pattern (diagonal steps weigh twice the distance of horizontal or vertical
// ones) from (0, 0) to the last frames of both, inside `band`. Distances are
// Euclidean. \throw AlignmentError when the dimensions differ, either
// sequence is empty, the band does not fit them, or it holds more than
// `max_cells` cells, or `pauses` has not one flag per column (and per row).
DtwPath AlignFeatureSequences(const AudioFeatures& rows, const AudioFeatures& columns, const DtwBand& band,
                              std::size_t max_cells, const DtwPauseColumns* pauses = nullptr);

}  // namespace facerig
