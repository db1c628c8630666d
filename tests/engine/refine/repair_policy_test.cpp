// RepairPolicy on count sequences like those measured on the patients (docs/refinement.md).
#include "refine/repair_policy.h"

#include <gtest/gtest.h>

#include <vector>

namespace mesh4d::refine {
namespace {

using Next = RepairPolicy::Next;

// Feeds `counts` to the policy at its current level; returns the answers.
std::vector<Next> feed(RepairPolicy& policy, const std::vector<std::size_t>& counts) {
  std::vector<Next> answers;
  for (std::size_t c : counts) answers.push_back(policy.observe(c));
  return answers;
}

TEST(RepairPolicy, NoPinchesStops) {
  RepairPolicy policy;
  EXPECT_EQ(policy.observe(0), Next::stop);
}

TEST(RepairPolicy, AFallingCountGoesOn) {
  RepairPolicy policy;
  for (Next n : feed(policy, {839, 633, 508, 336, 261, 193, 144, 139, 94, 74, 31, 26, 20}))
    EXPECT_EQ(n, Next::repair);
}

TEST(RepairPolicy, AStalledLevelMovesToAFinerOne) {
  // The ventricle's first level: a low of 17, then four rounds above it.
  RepairPolicy policy;
  const auto answers = feed(policy, {31, 26, 20, 21, 17, 18, 19, 21, 22});
  for (std::size_t i = 0; i + 1 < answers.size(); ++i) EXPECT_EQ(answers[i], Next::repair) << i;
  EXPECT_EQ(answers.back(), Next::finer);
  // A level counts its own lows: the finer level starts afresh.
  policy.finer();
  EXPECT_EQ(policy.level(), 1);
  for (Next n : feed(policy, {22, 11, 17, 9, 5, 4})) EXPECT_EQ(n, Next::repair);
}

TEST(RepairPolicy, GrowthStopsOnlyAFinerLevel) {
  // At Δ/2 a count may rise for a while (Pat01 at the paper's spacing: 562, 594, 629, 600,
  // then 493); at Δ/4 a rise past 1.25 times the level's first count ends the repair (Pat04:
  // 1424, then 1840).
  RepairPolicy first;
  for (Next n : feed(first, {718, 670, 562, 594, 629, 600, 493})) EXPECT_EQ(n, Next::repair);
  RepairPolicy finer;
  finer.finer();
  EXPECT_EQ(finer.observe(1424), Next::repair);
  EXPECT_EQ(finer.observe(1700), Next::repair);  // below 1.25 × 1424 = 1780
  EXPECT_EQ(finer.observe(1840), Next::stop);
}

}  // namespace
}  // namespace mesh4d::refine
