// In periodic time the manifold steps look at the links the output has: a vertex of the covering
// past the middle sheet stands for its twin there (counted_vertex). Near the covering's cut-off
// ends the links are the cut-off's, not the cycle's: the repairs once took such vertices from the
// new pentatopes' vertices, mended their links, and the labels they moved went to every twin,
// into the middle sheet (Pat02 periodic with a covering of 8 frames each side, seed 7: two
// vertices at t ≈ 20 left non-manifold, and two myocardium pieces touching there).
#include "refine/manifold_scan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "domain/phantoms.h"
#include "domain/surface_oracle.h"

namespace mesh4d::refine {
namespace {

using delaunay::CellId;
using mesh4d::VertexId;

constexpr double kStart = 4, kPeriod = 6, kMargin = 3;  // the covering: t in [1, 13)

class CountedVertex : public ::testing::Test {
 protected:
  CountedVertex()
      : image_(domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5)),
        oracle_(image_),
        state_(oracle_, params()) {}

  static RefineParams params() {
    RefineParams p;
    p.delta = 2;
    p.period_start = kStart;
    p.period = kPeriod;
    p.period_margin = kMargin;
    return p;
  }

  // A point of the middle sheet with its copies one period below and above, where they lie in
  // the covering, each recorded for the twin lookups; returns the middle one's vertex.
  VertexId insert_with_copies(const Point4& p) {
    VertexId middle = delaunay::kNoVertex;
    for (const Point4& q : state_.covering.copies(p)) {
      if (!state_.covering.in_covering(q)) continue;
      const VertexId v = state_.tri.insert(q, delaunay::VertexKind::feature).vertex;
      state_.covering.add(v, q);
      if (state_.covering.in_middle(q[3])) middle = v;
    }
    return middle;
  }

  domain::LabelImage4 image_;
  domain::SurfaceOracle oracle_;
  RefinementState state_;
};

TEST_F(CountedVertex, APeriodicVertexPastTheMiddleSheetStandsForItsTwin) {
  ASSERT_TRUE(state_.covering.active());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> space(3, 12), time(kStart, kStart + kPeriod);
  std::vector<VertexId> middle;
  for (int i = 0; i < 300; ++i)
    middle.push_back(insert_with_copies({space(rng), space(rng), space(rng), time(rng)}));
  // A vertex in the margin with no twin in the middle sheet (the covering never holds one; a
  // cut-off end's vertex stands for nothing).
  const VertexId lone = state_.tri.insert({7, 7, 7, 2}, delaunay::VertexKind::feature).vertex;
  const auto& st = state_.tri.store();
  std::size_t copies = 0;
  for (VertexId u : middle) {
    EXPECT_EQ(counted_vertex(state_, u), u);
    for (int periods : {-1, 1}) {
      const VertexId copy = state_.covering.twin(state_.tri, u, periods);
      if (copy == delaunay::kNoVertex) continue;
      ++copies;
      EXPECT_EQ(counted_vertex(state_, copy), u) << "t " << st.point(copy)[3];
    }
  }
  EXPECT_GT(copies, 100u);
  EXPECT_EQ(counted_vertex(state_, lone), delaunay::kNoVertex);

  // Label 1 on two pentatopes of a middle vertex's star that share only that vertex, label 0
  // everywhere else: its link there is two spheres. Asked at a copy, the pair is the middle
  // vertex's, and the star collected is its star.
  std::vector<CellId> live;
  for (CellId c = 0; c < st.cell_slots(); ++c)
    if (st.is_live(c)) live.push_back(c);
  state_.admit(live);
  for (CellId c : live) state_.set_label(c, 0);
  std::vector<CellId> star, asked;
  bool found = false;
  for (VertexId u : middle) {
    const VertexId copy = state_.covering.twin(state_.tri, u, u % 2 ? 1 : -1);
    if (copy == delaunay::kNoVertex) continue;
    state_.tri.incident_cells(u, star);
    for (std::size_t a = 0; a < star.size() && !found; ++a)
      for (std::size_t b = a + 1; b < star.size() && !found; ++b) {
        if (!state_.info[star[a]].finite || !state_.info[star[b]].finite) continue;
        int shared = 0;
        for (VertexId x : st.cell(star[a]).v)
          shared += std::count(std::begin(st.cell(star[b]).v), std::end(st.cell(star[b]).v), x);
        if (shared != 1) continue;
        found = true;
        state_.set_label(star[a], 1);
        state_.set_label(star[b], 1);
        std::vector<NonManifoldVertex> failing;
        non_manifold_labels_at(state_, copy, asked, &failing);
        ASSERT_EQ(failing.size(), 1u);
        EXPECT_EQ(failing[0].vertex, u);
        EXPECT_EQ(failing[0].label, 1);
        std::sort(asked.begin(), asked.end());
        std::sort(star.begin(), star.end());
        EXPECT_EQ(asked, star);
      }
    if (found) break;
  }
  EXPECT_TRUE(found) << "no star with two pentatopes that share one vertex";
}

TEST(CountedVertexOpenTime, EveryVertexStandsForItself) {
  const domain::LabelImage4 image = domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 2;
  RefinementState state(oracle, params);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> at(2, 13);
  for (int i = 0; i < 50; ++i) {
    const VertexId v = state.tri.insert({at(rng), at(rng), at(rng), at(rng)}).vertex;
    EXPECT_EQ(counted_vertex(state, v), v);
  }
}

}  // namespace
}  // namespace mesh4d::refine
