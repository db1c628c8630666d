// The default time scale: the boundary's motion between frames measured on shapes whose motion
// is known, and the rule max(Δ, motion).
#include "domain/time_scale.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mesh4d::domain {
namespace {

// A ball of radius radius(t) voxels around center(t) in every frame, spacing `h` in space.
template <class Radius, class Center>
LabelImage4 ball_over_time(std::size_t frames, double h, Radius radius, Center center) {
  const std::size_t n = 40;
  LabelImage4 image({n, n, n, frames}, {h, h, h, 1});
  for (std::size_t t = 0; t < frames; ++t)
    for (std::size_t z = 0; z < n; ++z)
      for (std::size_t y = 0; y < n; ++y)
        for (std::size_t x = 0; x < n; ++x) {
          const double dx = x - center(t), dy = y - 20.0, dz = z - 20.0;
          if (std::sqrt(dx * dx + dy * dy + dz * dz) <= radius(t)) image.set(x, y, z, t, 1);
        }
  return image;
}

TEST(TimeScale, AGrowingBallsBoundaryMovesByItsGrowthPerFrame) {
  // Radius 8, 9.5, 11 voxels of 2 mm: the boundary moves 1.5 voxels = 3 mm per frame.
  const LabelImage4 image = ball_over_time(
      3, 2.0, [](std::size_t t) { return 8 + 1.5 * t; }, [](std::size_t) { return 20.0; });
  EXPECT_NEAR(boundary_motion_per_frame(image), 3.0, 0.45);
}

TEST(TimeScale, AMovingBallsBoundaryMovesByHalfItsStepOnAverage) {
  // Along its normal, a sphere shifted by s moves by |n·s|, s/2 on average over the sphere. The
  // largest pair counts: steps of 1 and then 4 voxels (of 1 mm) give 2 mm, not the mean.
  const LabelImage4 image = ball_over_time(
      3, 1.0, [](std::size_t) { return 8.0; },
      [](std::size_t t) { return t == 0   ? 14.0
                                 : t == 1 ? 15.0
                                          : 19.0; });
  EXPECT_NEAR(boundary_motion_per_frame(image), 2.0, 0.3);
}

TEST(TimeScale, StillAndSingleFramesDoNotMove) {
  const auto still = ball_over_time(
      4, 1.0, [](std::size_t) { return 6.0; }, [](std::size_t) { return 20.0; });
  EXPECT_EQ(boundary_motion_per_frame(still), 0.0);
  const auto single = ball_over_time(
      1, 1.0, [](std::size_t) { return 6.0; }, [](std::size_t) { return 20.0; });
  EXPECT_EQ(boundary_motion_per_frame(single), 0.0);
}

TEST(TimeScale, AnObjectAppearingOrAPaddedFrameIsNoMotion) {
  // Frames 0 and 3 empty (as the closing pads them, or before a shape appears); the ball grows
  // by 1.5 voxels of 2 mm between frames 1 and 2.
  const LabelImage4 image = ball_over_time(
      4, 2.0, [](std::size_t t) { return t == 0 || t == 3 ? -1.0 : 6.5 + 1.5 * t; },
      [](std::size_t) { return 20.0; });
  EXPECT_NEAR(boundary_motion_per_frame(image), 3.0, 0.45);
}

TEST(TimeScale, TheDefaultIsTheLargerOfDeltaAndTheMotion) {
  const LabelImage4 image = ball_over_time(
      3, 2.0, [](std::size_t t) { return 8 + 1.5 * t; }, [](std::size_t) { return 20.0; });
  const double motion = boundary_motion_per_frame(image);
  EXPECT_EQ(automatic_time_scale(image, 5), 5.0);
  EXPECT_EQ(automatic_time_scale(image, 1), motion);
}

TEST(TimeScale, SettingTheTimeSpacingKeepsTheOriginInFrames) {
  LabelImage4 image({2, 2, 2, 3}, {1, 1, 1, 40}, {0, 0, 0, -80});  // frame 0 at frame -2
  image.set_time_spacing(5);
  EXPECT_EQ(image.spacing()[3], 5.0);
  EXPECT_EQ(image.origin()[3], -10.0);
  EXPECT_EQ(image.voxel_center(0, 0, 0, 2)[3], 0.0);
  EXPECT_THROW(image.set_time_spacing(0), ImageError);
  EXPECT_THROW(image.set_time_spacing(std::nan("")), ImageError);
  EXPECT_EQ(image.spacing()[3], 5.0);
}

}  // namespace
}  // namespace mesh4d::domain
