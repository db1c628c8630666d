// The image's side of the topology certificate: pieces by face connectivity (a corner or edge
// contact does not join), voxel volumes per label and per frame; against an independent count
// over every pair of voxels on small random images.
#include "domain/label_census.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <random>
#include <set>

#include "domain/phantoms.h"

namespace mesh4d::domain {
namespace {

const LabelCensus::PerLabel& of(const LabelCensus& c, Label l) {
  for (const auto& x : c.labels)
    if (x.label == l) return x;
  throw std::out_of_range("no such label");
}

TEST(LabelCensus, OnlyFacesJoinAndVolumesAreTheVoxels) {
  LabelImage4 image({4, 4, 4, 3}, {1, 2, 3, 5});
  image.set(1, 1, 1, 1, 1);
  image.set(2, 2, 1, 1, 1);  // an edge contact: a second piece
  image.set(2, 2, 2, 2, 1);  // a corner contact across time too: a third
  image.set(1, 1, 2, 1, 2);  // a face contact, but another label
  image.set(1, 1, 3, 1, 2);  // joined to it through a face
  const LabelCensus c = take_census(image);
  ASSERT_EQ(c.labels.size(), 2u);
  EXPECT_EQ(of(c, 1).components, 3u);
  EXPECT_EQ(of(c, 2).components, 1u);
  EXPECT_EQ(of(c, 1).voxels, 3u);
  EXPECT_DOUBLE_EQ(of(c, 1).volume, 3 * 1 * 2 * 3 * 5.0);
  ASSERT_EQ(c.frame_times.size(), 3u);
  EXPECT_DOUBLE_EQ(c.frame_times[1] - c.frame_times[0], 5.0);
  EXPECT_TRUE(c.frame_volumes[0].empty());
  EXPECT_DOUBLE_EQ(c.frame_volumes[1].at(1), 2 * 6.0);
  EXPECT_DOUBLE_EQ(c.frame_volumes[2].at(1), 6.0);
  EXPECT_DOUBLE_EQ(c.frame_volumes[1].at(2), 2 * 6.0);
}

TEST(LabelCensus, AgreesWithACountOverEveryPairOfVoxels) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    LabelImage4 image({5, 4, 3, 3}, {1, 1, 1, 1});
    std::uniform_int_distribution<int> label(0, 2);
    for (std::size_t i = 0; i < image.voxel_count(); ++i)
      image.set(i, static_cast<Label>(label(rng)));
    // Pieces: voxels joined when their coordinates differ by one along exactly one axis.
    const auto& d = image.dims();
    const std::size_t n = image.voxel_count();
    std::vector<std::size_t> piece(n);
    for (std::size_t i = 0; i < n; ++i) piece[i] = i;
    const auto coords = [&](std::size_t i) {
      return std::array<long, 4>{long(i % d[0]), long(i / d[0] % d[1]),
                                 long(i / (d[0] * d[1]) % d[2]), long(i / (d[0] * d[1] * d[2]))};
    };
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
          if (image.at(i) == 0 || image.at(i) != image.at(j)) continue;
          const auto a = coords(i), b = coords(j);
          long off = 0;
          for (int k = 0; k < 4; ++k) off += std::abs(a[k] - b[k]);
          if (off == 1 && piece[j] > piece[i]) piece[j] = piece[i], changed = true;
        }
    }
    std::map<Label, std::set<std::size_t>> pieces;
    for (std::size_t i = 0; i < n; ++i)
      if (image.at(i) != 0) pieces[image.at(i)].insert(piece[i]);
    const LabelCensus c = take_census(image);
    for (const auto& per : c.labels)
      EXPECT_EQ(per.components, pieces[per.label].size())
          << "trial " << trial << ", label " << per.label;
  }
}

TEST(LabelCensus, PhantomsHaveTheirKnownPieces) {
  EXPECT_EQ(of(take_census(hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5)), 1).components,
            1u);
  const LabelCensus ventricle = take_census(beating_ventricle_phantom());
  EXPECT_EQ(of(ventricle, 1).components, 1u);
  EXPECT_EQ(of(ventricle, 2).components, 1u);
}

}  // namespace
}  // namespace mesh4d::domain
