// The relabeling's reading of the cycle of labels around a triangle (refine/link_labels.h).
#include "refine/link_labels.h"

#include <gtest/gtest.h>

namespace mesh4d::refine {
namespace {

using Labels = std::vector<domain::Label>;

Labels applied(Labels labels, const LinkMoves& moves) {
  for (const auto& [i, l] : moves) labels[i] = l;
  return labels;
}

TEST(LinkLabels, ArcsWrapAroundTheEndOfTheCycle) {
  // 1 1 0 2 1: label 1 has one arc of three positions, from 4 through 0 and 1.
  const Labels labels{1, 1, 0, 2, 1};
  const auto ones = label_arcs(labels, 1, true);
  ASSERT_EQ(ones.size(), 1u);
  EXPECT_EQ(ones[0].begin, 4u);
  EXPECT_EQ(ones[0].length, 3u);
  const auto gaps = label_arcs(labels, 1, false);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].begin, 2u);
  EXPECT_EQ(gaps[0].length, 2u);
  EXPECT_EQ(label_arcs(Labels{2, 2, 2}, 2, true).size(), 1u);
  EXPECT_TRUE(label_arcs(Labels{2, 2, 2}, 1, true).empty());
}

TEST(LinkLabels, SplitLabelsCountsPinchedRegionsButNotTheBackground) {
  EXPECT_EQ(split_labels({1, 1, 2, 2, 0}), 0);
  EXPECT_EQ(split_labels({1, 0, 1, 0}), 1);           // 1 pinched; the background is not a region
  EXPECT_EQ(split_labels({2, 2, 1, 2, 2, 1, 1}), 2);  // a checkerboard of two labels
  EXPECT_EQ(split_labels({1, 2, 1, 0, 2}), 2);
}

TEST(LinkLabels, JoiningMovesLeaveTheLabelInOneArc) {
  const Labels cases[] = {
      {1, 0, 1, 0}, {1, 1, 0, 1, 2, 2}, {2, 2, 1, 2, 2, 1, 1}, {1, 2, 1, 0, 2, 0}};
  for (const Labels& labels : cases)
    for (domain::Label l : {1, 2}) {
      const auto options = joining_moves(labels, l);
      if (label_arcs(labels, l, true).size() < 2) {
        EXPECT_TRUE(options.empty());
        continue;
      }
      ASSERT_EQ(options.size(), 3 * label_arcs(labels, l, true).size());
      for (const LinkMoves& o : options) {
        EXPECT_FALSE(o.empty());
        EXPECT_EQ(label_arcs(applied(labels, o), l, true).size(), 1u);
      }
    }
}

TEST(LinkLabels, FillingKeepsTheLongestGapAndCuttingTheLongestArc) {
  // 1 0 0 0 1 2: the gaps of 1 are {1,2,3} and {5}; filling takes only position 5. The arcs of
  // 1 are {0} and {4}, equally long: cutting moves one of them to a neighbor's label.
  const Labels labels{1, 0, 0, 0, 1, 2};
  const auto options = joining_moves(labels, 1);
  ASSERT_EQ(options.size(), 6u);
  EXPECT_EQ(options[0], (LinkMoves{{5, 1}}));
  EXPECT_EQ(options[1].size(), 1u);
  EXPECT_EQ(options[2].size(), 1u);
  // Then the options that keep the other gap and the other arc.
  EXPECT_EQ(options[3], (LinkMoves{{1, 1}, {2, 1}, {3, 1}}));
  EXPECT_EQ(options[4].size(), 1u);
  EXPECT_NE(options[4], options[1]);
  // The checkerboard {2 2 1 2 2 1 1}: giving the lone 1 to label 2 joins both labels at once.
  EXPECT_EQ(
      split_labels(applied({2, 2, 1, 2, 2, 1, 1}, joining_moves({2, 2, 1, 2, 2, 1, 1}, 2)[0])), 0);
}

TEST(LinkLabels, EveryGapCanBeTheOneKept) {
  // 1 0 0 0 1 2 2 2: two gaps of three. Where the 2s cannot move (free vertices), filling the
  // background gap is the only way to join the 1s; both fills are offered.
  const Labels labels{1, 0, 0, 0, 1, 2, 2, 2};
  const auto options = joining_moves(labels, 1);
  ASSERT_EQ(options.size(), 6u);
  bool fills_background = false, fills_twos = false;
  for (const LinkMoves& o : options) {
    EXPECT_EQ(label_arcs(applied(labels, o), 1, true).size(), 1u);
    fills_background = fills_background || o == LinkMoves{{1, 1}, {2, 1}, {3, 1}};
    fills_twos = fills_twos || o == LinkMoves{{5, 1}, {6, 1}, {7, 1}};
  }
  EXPECT_TRUE(fills_background);
  EXPECT_TRUE(fills_twos);
}

}  // namespace
}  // namespace mesh4d::refine
