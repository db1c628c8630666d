// The image's side of the topology certificate: pieces by face connectivity (a corner or edge
// contact does not join) and as the label function joins them (a diagonal contact joins when the
// label function gives its block's center to the label), voxel volumes per label and per frame;
// both counts against independent ones over every pair of voxels on small random images.
#include "domain/label_census.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <random>
#include <set>

#include "domain/phantoms.h"
#include "domain/surface_oracle.h"

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
  EXPECT_EQ(of(c, 1).face_components, 3u);
  EXPECT_EQ(of(c, 2).face_components, 1u);
  // The label function: label 1 has the most voxels of the edge contact's 2×2 block and of the
  // corner contact's 2⁴ block (the rest background), so it joins all three.
  EXPECT_EQ(of(c, 1).components, 1u);
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

// A diagonal contact goes to the label that the block's center has: the most voxels of the
// block, ties to the higher label.
TEST(LabelCensus, TheLabelFunctionDecidesEachDiagonalContact) {
  LabelImage4 image({4, 4, 3, 3}, {1, 1, 1, 1});
  // A 2×2 block in the x–y plane: label 1 on one diagonal, label 2 on the other. Each has two
  // voxels; the tie goes to 2, whose pair is joined, and 1's pair is not.
  image.set(1, 1, 1, 1, 1);
  image.set(2, 2, 1, 1, 1);
  image.set(2, 1, 1, 1, 2);
  image.set(1, 2, 1, 1, 2);
  LabelCensus c = take_census(image);
  EXPECT_EQ(of(c, 1).components, 2u);
  EXPECT_EQ(of(c, 2).components, 1u);
  // With background on the other diagonal instead, label 1 wins its block's center.
  image.set(2, 1, 1, 1, 0);
  image.set(1, 2, 1, 1, 0);
  c = take_census(image);
  EXPECT_EQ(of(c, 1).components, 1u);
  EXPECT_EQ(of(c, 1).face_components, 2u);
  // An edge contact in a 2×2×2 block whose other six voxels are label 2: 2 has the center.
  LabelImage4 cube({4, 4, 4, 3}, {1, 1, 1, 1});
  for (std::size_t z = 1; z < 3; ++z)
    for (std::size_t y = 1; y < 3; ++y)
      for (std::size_t x = 1; x < 3; ++x) cube.set(x, y, z, 1, 2);
  cube.set(1, 1, 1, 1, 1);
  cube.set(2, 2, 2, 1, 1);
  EXPECT_EQ(of(take_census(cube), 1).components, 2u);
}

// Independent counts over every pair of voxels: by faces (coordinates differing by one along
// exactly one axis), and as the label function joins them (also opposite corners of a block of
// 2^k voxels whose label counts, with the offsets the oracle uses, favour their label).
TEST(LabelCensus, AgreesWithACountOverEveryPairOfVoxels) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    LabelImage4 image({5, 4, 3, 3}, {1, 1, 1, 1});
    std::uniform_int_distribution<int> label(0, 2);
    for (std::size_t i = 0; i < image.voxel_count(); ++i)
      image.set(i, static_cast<Label>(label(rng)));
    const auto& d = image.dims();
    const std::size_t n = image.voxel_count();
    const std::vector<double> beta = SurfaceOracle::label_offsets(image.labels());
    const auto coords = [&](std::size_t i) {
      return std::array<long, 4>{long(i % d[0]), long(i / d[0] % d[1]),
                                 long(i / (d[0] * d[1]) % d[2]), long(i / (d[0] * d[1] * d[2]))};
    };
    // Whether the block spanned by voxels i and j (corners of each other's) gives its center to
    // their label: the counts of its voxels' labels, weighted as the label function weighs them.
    const auto center_is = [&](std::size_t i, std::size_t j, Label l) {
      const auto a = coords(i), b = coords(j);
      std::map<Label, double> value;
      for (std::size_t k = 0; k < n; ++k) {
        const auto c = coords(k);
        bool in = true;
        for (int x = 0; x < 4; ++x)
          in = in && std::min(a[x], b[x]) <= c[x] && c[x] <= std::max(a[x], b[x]);
        if (in) value[image.at(k)] += 1;
      }
      double blocks = 0;
      for (const auto& [m, count] : value) blocks += count;
      Label best = 0;
      double top = -1;
      for (const auto& [m, count] : value)
        if (count / blocks + beta[m] > top) top = count / blocks + beta[m], best = m;
      return best == l;
    };
    for (const bool by_faces : {true, false}) {
      std::vector<std::size_t> piece(n);
      for (std::size_t i = 0; i < n; ++i) piece[i] = i;
      for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t i = 0; i < n; ++i)
          for (std::size_t j = 0; j < n; ++j) {
            if (image.at(i) == 0 || image.at(i) != image.at(j) || piece[j] <= piece[i]) continue;
            const auto a = coords(i), b = coords(j);
            long off = 0, far = 0;
            for (int k = 0; k < 4; ++k)
              off += std::abs(a[k] - b[k]), far = std::max(far, std::abs(a[k] - b[k]));
            const bool joins = off == 1 || (!by_faces && far == 1 && center_is(i, j, image.at(i)));
            if (joins) piece[j] = piece[i], changed = true;
          }
      }
      std::map<Label, std::set<std::size_t>> pieces;
      for (std::size_t i = 0; i < n; ++i)
        if (image.at(i) != 0) pieces[image.at(i)].insert(piece[i]);
      const LabelCensus c = take_census(image);
      for (const auto& per : c.labels)
        EXPECT_EQ(by_faces ? per.face_components : per.components, pieces[per.label].size())
            << "trial " << trial << ", label " << per.label << (by_faces ? ", faces" : "");
    }
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
