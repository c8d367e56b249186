#include "facerig/runtime/alignment/dtw_align.h"

#include <vector>

#include <catch2/catch.hpp>

namespace facerig {
namespace {

// One-dimensional "features" straight from values.
AudioFeatures Sequence(const std::vector<float>& values) {
  AudioFeatures features;
  features.sample_rate = 100;
  features.hop_samples = 1;
  features.window_samples = 1;
  features.dimension = 1;
  features.values = values;
  features.log_energy.assign(values.size(), 0.0f);
  return features;
}

DtwBand FullBand(std::size_t rows, std::size_t columns) {
  DtwBand band;
  band.first.assign(rows, 0);
  band.last.assign(rows, columns - 1);
  return band;
}

TEST_CASE("AlignFeatureSequences: a stretched copy is found frame for frame", "[dtw]") {
  const AudioFeatures rows = Sequence({0, 1, 2, 3, 4, 5});
  // 2 and 4 held three times as long; 1 skipped.
  const AudioFeatures columns = Sequence({0, 2, 2, 2, 3, 4, 4, 4, 5});
  const DtwPath path = AlignFeatureSequences(rows, columns, FullBand(6, 9), 1000);
  CHECK(path.first_column == std::vector<std::size_t>{0, 0, 1, 4, 5, 8});
  CHECK(path.last_column == std::vector<std::size_t>{0, 0, 3, 4, 7, 8});
  CHECK(path.cost == Approx(1.0 / 15.0));  // only frame 1 (value 1) matches nothing exactly
}

TEST_CASE("MakeDtwBand: a connected band around the centre line", "[dtw]") {
  // A steep centre (5 columns per row) with a narrow radius: rows stay connected.
  const std::vector<double> centre = {0, 5, 10, 15, 20};
  const DtwBand band = MakeDtwBand(centre, 21, 1);
  REQUIRE(band.first.size() == 5);
  CHECK(band.first[0] == 0);
  CHECK(band.last[4] == 20);
  for (std::size_t i = 1; i < 5; ++i) {
    CHECK(band.first[i] <= band.last[i - 1] + 1);
    CHECK(band.first[i] >= band.first[i - 1]);
  }
  CHECK(band.cell_count() < 5 * 21);
  std::vector<float> column_values(21);
  for (std::size_t j = 0; j < 21; ++j) column_values[j] = static_cast<float>(j) / 5.0f;
  const DtwPath path = AlignFeatureSequences(Sequence({0, 1, 2, 3, 4}), Sequence(column_values), band, 1000);
  CHECK(path.last_column.back() == 20);
}

TEST_CASE("AlignFeatureSequences: invalid inputs are AlignmentErrors", "[dtw]") {
  const AudioFeatures a = Sequence({0, 1, 2});
  const AudioFeatures b = Sequence({0, 1, 2, 3});
  CHECK_THROWS_AS(AlignFeatureSequences(Sequence({}), b, DtwBand{}, 1000), AlignmentError);
  AudioFeatures wide = b;
  wide.dimension = 2;
  wide.values = {0, 0, 1, 1, 2, 2, 3, 3};
  CHECK_THROWS_AS(AlignFeatureSequences(a, wide, FullBand(3, 4), 1000), AlignmentError);
  CHECK_THROWS_AS(AlignFeatureSequences(a, b, FullBand(2, 4), 1000), AlignmentError);  // wrong row count
  DtwBand gap = FullBand(3, 4);
  gap.first = {0, 3, 3};
  gap.last = {0, 3, 3};  // row 1 cannot be reached from row 0's column 0
  CHECK_THROWS_AS(AlignFeatureSequences(a, b, gap, 1000), AlignmentError);
  try {
    AlignFeatureSequences(a, b, FullBand(3, 4), 11);  // 12 cells needed
    FAIL("no error");
  } catch (const AlignmentError& e) {
    CHECK_THAT(e.what(), Catch::Matchers::Contains("12 cells"));
  }
}

}  // namespace
}  // namespace facerig
