#include "domain/periodic_time.h"

#include <gtest/gtest.h>

#include <cmath>

#include "domain/label_census.h"
#include "domain/phantoms.h"

namespace mesh4d::domain {
namespace {

TEST(PeriodicTime, TheCycleSpansHalfAFrameBeyondItsEndFrames) {
  const LabelImage4 cycle({4, 4, 4, 10}, {1, 1, 1, 0.7}, {0, 0, 0, 3});
  const TimePeriod period = cycle_period(cycle);
  EXPECT_NEAR(period.start, 3 - 0.35, kTimeQuantum);
  EXPECT_NEAR(period.length, 7, kTimeQuantum);
  EXPECT_THROW(cycle_period(LabelImage4({4, 4, 4, 1}, {1, 1, 1, 1})), ImageError);
}

TEST(PeriodicTime, WrappedTimesLieInThePeriodAndTheirCopiesAreExact) {
  const TimePeriod period = cycle_period(LabelImage4({2, 2, 2, 13}, {1, 1, 1, 0.37}));
  for (double t : {-100.123456789, -0.185, 0.0, 1.3, 4.625, 4.81, 37.77777}) {
    const double w = period.wrap(t);
    EXPECT_GE(w, period.start) << t;
    EXPECT_LT(w, period.start + period.length) << t;
    // On the grid, so a copy one period away is exact and comes back to the same time.
    EXPECT_EQ(w, snap_time(w));
    EXPECT_EQ(period.wrap(w + period.length), w);
    EXPECT_EQ((w + period.length) - period.length, w);
    EXPECT_FALSE(std::signbit(snap_time(-1e-12)));  // zero, not −0.0: it hashes as 0.0
    const double turns = (t - w) / period.length;
    EXPECT_NEAR(turns, std::round(turns), 1e-6) << t;
  }
}

TEST(PeriodicTime, TheCoveringIsTheCycleThreeTimesWithTheMiddleInPlace) {
  const LabelImage4 cycle = appearing_ball_phantom({20, 12, 12, 6}, {1, 1, 1, 2});
  const LabelImage4 tiled = tile_cycle(cycle);
  ASSERT_EQ(tiled.dims()[3], 18u);
  EXPECT_EQ(tiled.voxel_center(0, 0, 0, 6), cycle.voxel_center(0, 0, 0, 0));
  for (std::size_t copy = 0; copy < 3; ++copy)
    for (std::size_t i = 0; i < cycle.voxel_count(); ++i)
      ASSERT_EQ(tiled.at(copy * cycle.voxel_count() + i), cycle.at(i));
}

TEST(PeriodicTime, APieceAcrossTheEndOfTheCycleIsOnePiece) {
  // The appearing ball lives from frame 10 over the end of the 12-frame cycle into its start:
  // two pieces of the image as it stands, one of the cycle.
  const LabelImage4 across = appearing_ball_phantom({36, 24, 24, 12}, {1, 1, 1, 1}, 10);
  using Pieces = std::pair<std::size_t, std::size_t>;  // label function's, face-connected
  const auto count = [](const LabelCensus& c, Label l) {
    for (const auto& per : c.labels)
      if (per.label == l) return Pieces(per.components, per.face_components);
    return Pieces(0, 0);
  };
  EXPECT_EQ(count(take_census(across), 2), Pieces(2, 2));
  EXPECT_EQ(count(take_periodic_census(across), 2), Pieces(1, 1));
  // The beating ball spans every frame: one piece either way.
  EXPECT_EQ(count(take_periodic_census(across), 1).first, 1u);
  // Appearing mid-cycle, the ball is one piece either way.
  const LabelImage4 inside = appearing_ball_phantom({36, 24, 24, 12}, {1, 1, 1, 1}, 3);
  EXPECT_EQ(count(take_census(inside), 2).first, 1u);
  EXPECT_EQ(count(take_periodic_census(inside), 2).first, 1u);
}

}  // namespace
}  // namespace mesh4d::domain
