// Repeating the end frames: dims, origin and labels, and every original frame at its old time.
#include "domain/time_extension.h"

#include <gtest/gtest.h>

namespace mesh4d::domain {
namespace {

TEST(TimeExtension, EndFramesAreRepeatedAndOriginalFramesKeepTheirTime) {
  LabelImage4 image({3, 2, 2, 4}, {1, 1, 1, 2.5}, {0, 0, 0, 10});
  for (std::size_t t = 0; t < 4; ++t) image.set(t % 3, 0, 0, t, static_cast<Label>(t + 1));
  const LabelImage4 longer = extend_time(image, 2);
  ASSERT_EQ(longer.dims()[3], 8u);
  EXPECT_DOUBLE_EQ(longer.origin()[3], 5.0);
  for (std::size_t t = 0; t < 4; ++t) {
    EXPECT_DOUBLE_EQ(longer.voxel_center(0, 0, 0, t + 2)[3], image.voxel_center(0, 0, 0, t)[3]);
    EXPECT_EQ(longer.at(t % 3, 0, 0, t + 2), t + 1);
  }
  for (std::size_t t : {0, 1}) EXPECT_EQ(longer.at(0, 0, 0, t), 1);  // frame 0 repeated
  for (std::size_t t : {6, 7}) EXPECT_EQ(longer.at(0, 0, 0, t), 4);  // frame 3 repeated
  EXPECT_EQ(extend_time(image, 0).dims()[3], 4u);
  EXPECT_THROW(extend_time(image, kMaxTimeExtension + 1), ImageError);
}

}  // namespace
}  // namespace mesh4d::domain
