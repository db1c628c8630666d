// The time caps' ghost frames: where they go, their labels, and the frames' times.
#include "domain/time_caps.h"

#include <gtest/gtest.h>

namespace mesh4d::domain {
namespace {

TEST(TimeCaps, GhostFramesMirrorTheEndFramesWithTwinLabels) {
  LabelImage4 image({3, 2, 2, 4}, {1, 1, 1, 2.5}, {0, 0, 0, 10});
  for (std::size_t t = 0; t < 4; ++t) image.set(1, 1, 1, t, 1);
  image.set(0, 0, 0, 3, 3);  // label 3 only in the last frame
  TimeCaps caps;
  std::string warning;
  const LabelImage4 capped = add_time_caps(image, 2, &caps, &warning);
  EXPECT_TRUE(warning.empty());
  EXPECT_EQ(caps.frames, 2u);
  ASSERT_EQ(capped.dims()[3], 8u);
  EXPECT_DOUBLE_EQ(capped.origin()[3], 5.0);
  for (std::size_t t = 0; t < 4; ++t)
    EXPECT_DOUBLE_EQ(capped.voxel_center(0, 0, 0, t + 2)[3], image.voxel_center(0, 0, 0, t)[3]);
  // Ghosts above every label, in the order of the labels they mirror: 1 → 4, 3 → 5.
  EXPECT_EQ(caps.real_of.at(4), 1);
  EXPECT_EQ(caps.real_of.at(5), 3);
  EXPECT_FALSE(caps.is_ghost(1));
  EXPECT_FALSE(caps.is_ghost(3));
  for (std::size_t t : {0, 1}) {
    EXPECT_EQ(capped.at(1, 1, 1, t), 4);
    EXPECT_EQ(capped.at(0, 0, 0, t), 0);
  }
  for (std::size_t t : {6, 7}) {
    EXPECT_EQ(capped.at(1, 1, 1, t), 4);
    EXPECT_EQ(capped.at(0, 0, 0, t), 5);
  }
  EXPECT_EQ(capped.at(1, 1, 1, 2), 1);
  EXPECT_EQ(capped.at(0, 0, 0, 5), 3);
}

TEST(TimeCaps, EndsWithoutForegroundGetNone) {
  LabelImage4 image({2, 2, 2, 5}, {1, 1, 1, 1});
  image.set(0, 0, 0, 2, 1);  // a shape that appears mid-cycle: its caps are its own
  TimeCaps caps;
  std::string warning;
  const LabelImage4 capped = add_time_caps(image, 3, &caps, &warning);
  EXPECT_EQ(capped.dims()[3], 5u);
  EXPECT_EQ(caps.frames, 0u);
  EXPECT_FALSE(caps.is_ghost(2));
  image.set(0, 0, 0, 4, 1);  // now the last frame has it
  const LabelImage4 one_end = add_time_caps(image, 3, &caps, &warning);
  EXPECT_EQ(one_end.dims()[3], 8u);
  EXPECT_DOUBLE_EQ(one_end.origin()[3], 0.0) << "nothing added before the first frame";
  EXPECT_EQ(one_end.at(0, 0, 0, 7), 2);
}

TEST(TimeCaps, TooManyLabelsForGhostsLeaveTheImageAsItIsAndSaySo) {
  LabelImage4 image({kMaxLabels, 1, 1, 2}, {1, 1, 1, 1});
  for (std::size_t x = 0; x < kMaxLabels / 2 + 1; ++x) image.set(x, 0, 0, 0, Label(x + 1));
  TimeCaps caps;
  std::string warning;
  const LabelImage4 capped = add_time_caps(image, 1, &caps, &warning);
  EXPECT_EQ(capped.dims()[3], 2u);
  EXPECT_EQ(caps.frames, 0u);
  EXPECT_NE(warning.find("too many for ghost labels"), std::string::npos) << warning;
}

TEST(TimeCaps, TheGhostsSpanDeltaOfTime) {
  EXPECT_EQ(cap_frames(5, 5), 1u);
  EXPECT_EQ(cap_frames(5, 2), 3u);
  EXPECT_EQ(cap_frames(1, 5), 1u);
}

}  // namespace
}  // namespace mesh4d::domain
