// Removal: long random insert/remove sequences with the checker after every operation, removal on
// degenerate lattices, and the refusals (hull, infinite, removed vertices).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "delaunay/checker.h"
#include "delaunay/triangulation.h"
#include "point_sets.h"

namespace mesh4d::delaunay {
namespace {

using mesh4d::testing::lattice;
using mesh4d::testing::random_points;

// Vertices whose star has no infinite pentatope (the removable ones).
std::vector<VertexId> interior_vertices(const Triangulation& t) {
  const auto& st = t.store();
  std::vector<char> on_hull(st.vertex_slots(), 0);
  for (CellId c = 0; c < st.cell_slots(); ++c)
    if (st.is_live(c) && st.is_infinite(c))
      for (VertexId v : st.cell(c).v) on_hull[v] = 1;
  std::vector<VertexId> out;
  for (VertexId v = 1; v < st.vertex_slots(); ++v)
    if (st.vertex(v).kind != VertexKind::removed && st.vertex(v).cell != kNoCell && !on_hull[v])
      out.push_back(v);
  return out;
}

// The 16 corners of [-1, 2]⁴ around the unit hypercube, as the refiner's bounding box: every
// point inserted in [0, 1]⁴ afterwards is interior, hence removable.
void insert_box(Triangulation& t) {
  for (int i = 0; i < 16; ++i)
    t.insert({i & 1 ? 2.0 : -1.0, i & 2 ? 2.0 : -1.0, i & 4 ? 2.0 : -1.0, i & 8 ? 2.0 : -1.0},
             VertexKind::box);
}

TEST(TriangulationRemove, RandomInsertRemoveSequenceValidAfterEveryOperation) {
  for (std::uint64_t seed : {3, 4}) {
    std::mt19937_64 rng(seed);
    Triangulation t;
    insert_box(t);
    t.insert_all(random_points(80, seed));
    const auto extra = random_points(150, seed + 100);
    std::size_t next = 0;
    for (int op = 0; op < 200; ++op) {
      if (rng() % 2 == 0 && next < extra.size()) {
        t.insert(extra[next++]);
      } else {
        const auto candidates = interior_vertices(t);
        ASSERT_FALSE(candidates.empty());
        const VertexId v = candidates[rng() % candidates.size()];
        const std::size_t before = t.number_of_vertices();
        ASSERT_TRUE(t.remove(v)) << "seed " << seed << " op " << op;
        EXPECT_EQ(t.number_of_vertices(), before - 1);
        EXPECT_EQ(t.store().vertex(v).kind, VertexKind::removed);
      }
      const CheckResult check = check_triangulation(t);
      ASSERT_TRUE(check.ok) << "seed " << seed << " op " << op << ": " << check.error;
    }
  }
}

TEST(TriangulationRemove, LatticeRemovalsStayValid) {
  // Removing from a lattice leaves co-spherical link vertices: the tie-break must glue the hole.
  Triangulation t;
  t.insert_all(lattice(4));
  std::mt19937_64 rng(8);
  for (int k = 0; k < 12; ++k) {
    const auto candidates = interior_vertices(t);
    if (candidates.empty()) break;
    ASSERT_TRUE(t.remove(candidates[rng() % candidates.size()]));
    const CheckResult check = check_triangulation(t);
    ASSERT_TRUE(check.ok) << "removal " << k << ": " << check.error;
  }
}

TEST(TriangulationRemove, RemoveThenReinsertGivesTheSameCellCount) {
  Triangulation t;
  const auto pts = random_points(300, 12);
  t.insert_all(pts);
  const std::size_t cells = t.number_of_finite_cells();
  const VertexId v = interior_vertices(t).front();
  const Point4 p = t.store().point(v);
  ASSERT_TRUE(t.remove(v));
  t.insert(p);  // a new id, but the same point set: the Delaunay triangulation is the same
  EXPECT_EQ(t.number_of_finite_cells(), cells);
  EXPECT_TRUE(check_triangulation(t).ok);
}

TEST(TriangulationRemove, RefusesHullInfiniteAndRemovedVertices) {
  Triangulation t;
  t.insert_all(random_points(100, 5));
  const auto& st = t.store();
  VertexId hull = kNoVertex;
  for (CellId c = 0; c < st.cell_slots() && hull == kNoVertex; ++c)
    if (st.is_live(c) && st.is_infinite(c))
      for (VertexId v : st.cell(c).v)
        if (v != kInfiniteVertex) hull = v;
  ASSERT_NE(hull, kNoVertex);
  const std::size_t cells = t.number_of_cells();
  EXPECT_FALSE(t.remove(hull));
  EXPECT_FALSE(t.remove(kInfiniteVertex));
  EXPECT_FALSE(t.remove(100000));
  EXPECT_EQ(t.number_of_cells(), cells);
  const VertexId v = interior_vertices(t).front();
  EXPECT_TRUE(t.remove(v));
  EXPECT_FALSE(t.remove(v));
  EXPECT_TRUE(check_triangulation(t).ok);
}

}  // namespace
}  // namespace mesh4d::delaunay
