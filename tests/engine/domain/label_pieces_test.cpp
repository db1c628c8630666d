// The label function's pieces two ways: the whole image at once (label_function_pieces, which
// the certificate counts) and walks from one voxel (for_each_joined_neighbor, each voxel's
// joins one by one): on random images each walk must cover exactly its voxel's piece.
#include "domain/label_pieces.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>
#include <vector>

#include "domain/face_components.h"
#include "domain/phantoms.h"
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

// The face pieces on several threads (slabs of frames flooded side by side, then joined): the
// same pieces, numbered alike, as one flood. The ventricle with salt of three labels has pieces
// of every size, many crossing the slabs' borders, some joined only through a later slab.
TEST(FacePieces, ThreadsGiveTheSamePieces) {
  LabelImage4 image = beating_ventricle_phantom({100, 100, 44, 15}, {1.77, 1.77, 6, 1});
  std::mt19937_64 rng(3);
  for (std::size_t i = 0; i < image.voxel_count(); ++i)
    if (rng() % 50 == 0) image.set(i, static_cast<Label>(rng() % 3));
  for (bool background : {true, false}) {
    const FacePieces one = face_pieces(image, background, 1);
    for (unsigned threads : {2u, 3u, 5u}) {
      SCOPED_TRACE(std::to_string(threads) + " threads, background " + std::to_string(background));
      const FacePieces many = face_pieces(image, background, threads);
      ASSERT_EQ(many.pieces.size(), one.pieces.size());
      for (std::size_t p = 0; p < one.pieces.size(); ++p) {
        ASSERT_EQ(many.pieces[p].label, one.pieces[p].label) << p;
        ASSERT_EQ(many.pieces[p].voxels, one.pieces[p].voxels) << p;
        ASSERT_EQ(many.pieces[p].touches_border, one.pieces[p].touches_border) << p;
      }
      EXPECT_TRUE(many.piece == one.piece);
    }
  }
}

}  // namespace
}  // namespace mesh4d::domain
