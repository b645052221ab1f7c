// What a job reached, summarised (core/job/tile_summary.h).
#include "job/tile_summary.h"

#include <gtest/gtest.h>

namespace tessera {
namespace {

TEST(TileSummary, MinMeanMaxOverTilesEachCountingOnce) {
  const TileSummary s = summarize_tiles({4, 8, 16}, {0.25, 0.5, 0.75});
  EXPECT_EQ(s.spp_min, 4u);
  EXPECT_EQ(s.spp_max, 16u);
  EXPECT_DOUBLE_EQ(s.spp_mean, 28.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.error_max, 0.75);
  EXPECT_DOUBLE_EQ(s.error_mean, 0.5);
}

TEST(TileSummary, AnErrorWithoutTwoSamplesPerPixelIsNotANumber) {
  EXPECT_EQ(error_text(0.0, 0), "n/a");
  EXPECT_EQ(error_text(0.0, 1), "n/a");
  EXPECT_EQ(error_text(0.0, 2), "0.0000");
  EXPECT_EQ(error_text(0.01234, 64), "0.0123");
}

}  // namespace
}  // namespace tessera
