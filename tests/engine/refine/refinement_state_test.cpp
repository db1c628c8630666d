// Every finite pentatope gets its ball, even one whose double determinant rounds to zero: a
// pentatope left without a ball took no rule and no label, and stood as a hole of the background
// inside a region, its free vertex on the region's boundary (a parallel run of the merging
// blobs).
#include "refine/refinement_state.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "delaunay/geometry.h"
#include "domain/phantoms.h"
#include "domain/surface_oracle.h"

namespace mesh4d::refine {
namespace {

using delaunay::CellId;

TEST(RefinementState, APentatopeTheDoublesCallFlatGetsItsBall) {
  domain::LabelImage4 image = domain::merging_blobs_phantom();
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 2.5;
  RefinementState state(oracle, params);
  // Four feature points nearly on one 2-plane of voxel-grid coordinates, and a free vertex:
  // their only finite pentatope (exact_circumcenter_test.cpp).
  const delaunay::Simplex4 s{
      {{36, 17, 17, 3.5299999999963623},
       {36, 20, 18, 2.5299999999963623},
       {37, 16, 19, 2.5299999999963623},
       {32.900112888041726, 17.366687198657118, 19.096635906583103, 1.6797198143089771},
       {37, 19, 20, 1.529999999996362}}};
  for (const Point4& p : s) state.tri.insert(p);
  ASSERT_FALSE(std::isfinite(delaunay::circumcenter(s)[0]));
  const auto& st = state.tri.store();
  std::vector<CellId> live;
  CellId finite_cell = delaunay::kNoCell;
  for (CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c)) continue;
    live.push_back(c);
    if (!st.is_infinite(c)) finite_cell = c;
  }
  ASSERT_NE(finite_cell, delaunay::kNoCell);
  state.admit(live);
  const CellInfo& info = state.info[finite_cell];
  ASSERT_TRUE(info.finite);
  for (const Point4& p : s) EXPECT_NEAR(distance(info.center, p), info.radius, 1e-9 * info.radius);
  // A sliver inside the blob: its label's, and R4's to remove.
  EXPECT_EQ(state.label_of(finite_cell), 1);
  EXPECT_LT(delaunay::normalized_volume(s, info.radius), params.sliver_bound);
  // No in-sphere question is decided from this ball alone.
  EXPECT_TRUE(std::isinf(info.center_error));
}

}  // namespace
}  // namespace mesh4d::refine
