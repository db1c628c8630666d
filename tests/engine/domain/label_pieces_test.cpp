// The label function's pieces two ways: the whole image at once (label_function_pieces, which
// the certificate counts) and walks from one voxel (for_each_joined_neighbor, each voxel's
// joins one by one): on random images each walk must cover exactly its voxel's piece.
#include "domain/label_pieces.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

#include "domain/surface_oracle.h"

namespace mesh4d::domain {
namespace {

TEST(LabelPieces, AWalkThroughJoinedNeighborsCoversExactlyItsPiece) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 30; ++trial) {
    LabelImage4 image({6, 5, 4, 3}, {1, 1, 1, 1});
    std::uniform_int_distribution<int> label(0, trial % 3 + 1);
    for (std::size_t i = 0; i < image.voxel_count(); ++i)
      image.set(i, static_cast<Label>(label(rng)));
    const FacePieces pieces = label_function_pieces(image);
    const std::vector<double> beta = SurfaceOracle::label_offsets(image.labels());
    for (std::size_t seed = 0; seed < image.voxel_count(); ++seed) {
      if (image.at(seed) == 0) {
        EXPECT_EQ(pieces.piece[seed], FacePieces::kNoPiece);
        continue;
      }
      std::set<std::size_t> seen{seed};
      std::vector<std::size_t> frontier{seed};
      while (!frontier.empty()) {
        const std::size_t v = frontier.back();
        frontier.pop_back();
        for_each_joined_neighbor(image, beta, v, [&](std::size_t j) {
          if (seen.insert(j).second) frontier.push_back(j);
        });
      }
      std::size_t in_piece = 0;
      for (std::size_t j = 0; j < image.voxel_count(); ++j)
        in_piece += pieces.piece[j] == pieces.piece[seed];
      ASSERT_EQ(seen.size(), in_piece) << "trial " << trial << ", voxel " << seed;
      for (std::size_t j : seen) ASSERT_EQ(pieces.piece[j], pieces.piece[seed]);
      ASSERT_EQ(pieces.pieces[pieces.piece[seed]].voxels, in_piece);
    }
  }
}

}  // namespace
}  // namespace mesh4d::domain
