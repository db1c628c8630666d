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
  // then 493); at Δ/4 a rise past 1.25 times the level's first count ends the repair at once
  // (Pat04: 1424, then 1840).
  RepairPolicy first;
  for (Next n : feed(first, {718, 670, 562, 594, 629, 600, 493})) EXPECT_EQ(n, Next::repair);
  RepairPolicy finer;
  finer.finer();
  EXPECT_EQ(finer.observe(1424), Next::repair);
  EXPECT_EQ(finer.observe(1840), Next::stop);
  // After its first round a finer level may rise a little (Pat02 at the files' spacing: 393,
  // 393, 355, 411, then down to 61).
  RepairPolicy later;
  later.finer();
  for (Next n : feed(later, {393, 393, 355, 411, 372, 312})) EXPECT_EQ(n, Next::repair);
  EXPECT_EQ(later.observe(492), Next::stop);  // past 1.25 × 393
}

TEST(RepairPolicy, AFinerLevelMustPayWithinTwoRounds) {
  // Pat02 at the files' spacing: level after its first round, then down to 61 —
  // it goes on. Pat05 at the files' spacing: 398, then 472 — it stops at once (the repair went
  // on to 427, 440, 465, then a Δ/8 level at 599: 1.6 s for nothing). Pat03 at the paper's
  // spacing: 495, 494, 526 — a new low, but under 5 %.
  RepairPolicy pays;
  pays.finer();
  for (Next n : feed(pays, {393, 393, 355, 411, 372, 312, 260, 221, 203, 180, 174, 166, 134}))
    EXPECT_EQ(n, Next::repair);
  RepairPolicy stalls;
  stalls.finer();
  EXPECT_EQ(feed(stalls, {398, 472}), (std::vector<Next>{Next::repair, Next::stop}));
  RepairPolicy barely;
  barely.finer();
  EXPECT_EQ(feed(barely, {495, 494, 526}),
            (std::vector<Next>{Next::repair, Next::repair, Next::stop}));
}

TEST(RepairPolicy, OnlyAFinerLevelThatCutTenPercentGoesFiner) {
  // Pat01 at the files' spacing: 106, 99, then four rounds above 99 (93 % of the
  // start): stop, where a Δ/8 level went from 118 to 155. The first level goes finer anyway.
  RepairPolicy finer;
  finer.finer();
  EXPECT_EQ(feed(finer, {106, 99, 110, 120, 111, 118}),
            (std::vector<Next>{Next::repair, Next::repair, Next::repair, Next::repair, Next::repair,
                               Next::stop}));
  RepairPolicy cut;
  cut.finer();
  EXPECT_EQ(feed(cut, {100, 80, 85, 86, 87, 88}).back(), Next::finer);
  RepairPolicy first;
  EXPECT_EQ(feed(first, {106, 106, 106, 106, 106}).back(), Next::finer);
}

}  // namespace
}  // namespace mesh4d::refine
