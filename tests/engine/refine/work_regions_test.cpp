// The blocks of space the parallel refiner's workers own (work_regions.h): a grid shaped like
// the box, numbered in Morton order, every point (outside the box too) in one block.
#include "refine/work_regions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace mesh4d::refine {
namespace {

TEST(WorkRegions, TheGridIsShapedLikeTheBoxAndCoversAllSpace) {
  // 100 × 100 × 100 × 12.5: 16 threads want about 512 blocks, cubes of side ~20.
  const std::array<Point4, 2> box = {Point4{0, 0, 0, 0}, Point4{100, 100, 100, 12.5}};
  const WorkRegions regions(box, 16);
  std::set<std::uint32_t> seen;
  std::set<std::uint32_t> along_t;
  for (double x = 0.5; x < 100; x += 1)
    for (double t = 0.05; t < 12.5; t += 0.1) {
      seen.insert(regions.block_of({x, 50, 50, t}));
      along_t.insert(regions.block_of({50, 50, 50, t}));
    }
  EXPECT_EQ(along_t.size(), 1u) << "12.5 long in t: one block across";
  EXPECT_GE(seen.size(), 4u);
  EXPECT_LE(seen.size(), 8u);
  for (std::uint32_t b : seen) EXPECT_LT(b, WorkRegions::kBlocks);
  // Outside the box (and NaN): the nearest block.
  EXPECT_EQ(regions.block_of({-5, -5, -5, -5}), regions.block_of({0, 0, 0, 0}));
  EXPECT_EQ(regions.block_of({500, 50, 50, 5}), regions.block_of({99.9, 50, 50, 5}));
  EXPECT_EQ(regions.block_of({NAN, 0, 0, 0}), regions.block_of({0, 0, 0, 0}));
}

// Points of one block's cube share it; the 16 blocks of the lowest 2×2×2×2 cube of blocks are
// numbers 0–15 (Morton order: a range of numbers is a compact piece of space); owners are kept.
TEST(WorkRegions, NearbyPointsShareABlockAndOwnersAreKept) {
  const std::array<Point4, 2> box = {Point4{0, 0, 0, 0}, Point4{64, 64, 64, 64}};
  WorkRegions regions(box, 8);  // 256 blocks wanted: 4 an axis, side 16
  EXPECT_EQ(regions.block_of({1, 1, 1, 1}), regions.block_of({15, 15, 15, 15}));
  EXPECT_NE(regions.block_of({15, 1, 1, 1}), regions.block_of({17, 1, 1, 1}));
  // The 16 blocks of the lower corner cube of 2×2×2×2 blocks come first in Morton order.
  std::set<std::uint32_t> corner;
  for (int i = 0; i < 16; ++i)
    corner.insert(regions.block_of({8.0 + 16 * (i & 1), 8.0 + 16 * ((i >> 1) & 1),
                                    8.0 + 16 * ((i >> 2) & 1), 8.0 + 16 * ((i >> 3) & 1)}));
  EXPECT_EQ(corner.size(), 16u);
  EXPECT_EQ(*corner.rbegin(), 15u);
  regions.set_owner(regions.block_of({40, 40, 40, 40}), 5);
  EXPECT_EQ(regions.owner(regions.block_of({41, 41, 41, 41})), 5u);
  EXPECT_EQ(regions.owner(regions.block_of({1, 1, 1, 1})), 0u);
}

}  // namespace
}  // namespace mesh4d::refine
