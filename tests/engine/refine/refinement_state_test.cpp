// Every finite pentatope gets its ball, even one whose double determinant rounds to zero: a
// pentatope left without a ball took no rule and no label, and stood as a hole of the background
// inside a region, its free vertex on the region's boundary (a parallel run of the merging
// blobs). Where the rounded center has no error bound, the ball is the exact one.
#include "refine/refinement_state.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "delaunay/circumballs.h"
#include "delaunay/exact_circumcenter.h"
#include "delaunay/geometry.h"
#include "domain/phantoms.h"
#include "domain/surface_oracle.h"

namespace mesh4d::refine {
namespace {

using delaunay::CellId;

// Four feature points nearly on one 2-plane of voxel-grid coordinates, and a free vertex, inside
// the merging blobs (exact_circumcenter_test.cpp); `shift` moves the free vertex in t.
delaunay::Simplex4 sliver(double shift) {
  return {{{36, 17, 17, 3.5299999999963623},
           {36, 20, 18, 2.5299999999963623},
           {37, 16, 19, 2.5299999999963623},
           {32.900112888041726, 17.366687198657118, 19.096635906583103, 1.6797198143089771 + shift},
           {37, 19, 20, 1.529999999996362}}};
}

class RefinementStateTest : public ::testing::Test {
 protected:
  RefinementStateTest() : image_(closed_blobs()), oracle_(image_), state_(oracle_, params()) {}

  static RefineParams params() {
    RefineParams p;
    p.delta = 2.5;
    return p;
  }
  // Triangulates s's vertices and admits every pentatope; returns the only finite one.
  CellId admitted(const delaunay::Simplex4& s) {
    for (const Point4& p : s) state_.tri.insert(p);
    const auto& st = state_.tri.store();
    std::vector<CellId> live;
    CellId finite_cell = delaunay::kNoCell;
    for (CellId c = 0; c < st.cell_slots(); ++c) {
      if (!st.is_live(c)) continue;
      live.push_back(c);
      if (!st.is_infinite(c)) finite_cell = c;
    }
    state_.admit(live);
    return finite_cell;
  }

  domain::LabelImage4 image_;
  domain::SurfaceOracle oracle_;
  RefinementState state_;

 private:
  static domain::LabelImage4 closed_blobs() {
    domain::LabelImage4 image = domain::merging_blobs_phantom();
    domain::validate_and_close(image);
    return image;
  }
};

TEST_F(RefinementStateTest, APentatopeTheDoublesCallFlatGetsItsBall) {
  const delaunay::Simplex4 s = sliver(0);
  ASSERT_FALSE(std::isfinite(delaunay::circumcenter(s)[0]));
  const CellId cell = admitted(s);
  ASSERT_NE(cell, delaunay::kNoCell);
  const CellInfo& info = state_.info[cell];
  ASSERT_TRUE(info.finite);
  for (const Point4& p : s) EXPECT_NEAR(distance(info.center, p), info.radius, 1e-9 * info.radius);
  // A sliver inside the blob: its label's, and R4's to remove.
  EXPECT_EQ(state_.label_of(cell), 1);
  EXPECT_LT(delaunay::normalized_volume(s, info.radius), params().sliver_bound);
  // No in-sphere question is decided from this ball alone.
  EXPECT_TRUE(std::isinf(info.center_error));
}

// The sliver with its free vertex moved 1e-13 in t: the doubles now give a finite center, but
// one without an error bound, a radius away from the exact one. The exact one is taken.
TEST_F(RefinementStateTest, APentatopeWithoutAnErrorBoundGetsItsExactBall) {
  const delaunay::Simplex4 s = sliver(1e-13);
  const Point4* vertices[4][5];
  for (auto& group : vertices)
    for (int k = 0; k < 5; ++k) group[k] = &s[k];
  delaunay::Circumball rounded[4];
  delaunay::circumballs4(vertices, rounded);
  ASSERT_TRUE(std::isfinite(rounded[0].center[0]));
  ASSERT_TRUE(std::isinf(rounded[0].center_error));
  const std::optional<Point4> exact = delaunay::exact_circumcenter(vertices[0]);
  ASSERT_TRUE(exact.has_value());
  const double radius = distance(*exact, s[0]);
  ASSERT_GT(distance(rounded[0].center, *exact), 0.5 * radius);

  const CellId cell = admitted(s);
  ASSERT_NE(cell, delaunay::kNoCell);
  const CellInfo& info = state_.info[cell];
  ASSERT_TRUE(info.finite);
  EXPECT_LT(distance(info.center, *exact), 1e-9 * radius);
  for (const Point4& p : s) EXPECT_NEAR(distance(info.center, p), info.radius, 1e-9 * info.radius);
  EXPECT_TRUE(std::isinf(info.center_error));
}

}  // namespace
}  // namespace mesh4d::refine
