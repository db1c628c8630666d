// Removal: long random insert/remove sequences with the checker after every operation, removal on
// degenerate lattices, both ways of filling a hole compared with each other and with the
// remaining points triangulated afresh, and the refusals (hull, infinite, removed vertices).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "delaunay/checker.h"
#include "delaunay/hole_filling.h"
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

// The finite pentatopes as sets of points (vertex ids differ between triangulations).
std::set<std::vector<Point4>> cells_by_points(const Triangulation& t) {
  const auto& st = t.store();
  std::set<std::vector<Point4>> cells;
  for (CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c) || st.is_infinite(c)) continue;
    std::vector<Point4> p;
    for (VertexId v : st.cell(c).v) p.push_back(st.point(v));
    std::sort(p.begin(), p.end());
    cells.insert(p);
  }
  return cells;
}

// The pentatopes of t's remaining vertices triangulated afresh, oldest first: the same
// perturbation order, so the same (unique) perturbed Delaunay triangulation.
std::set<std::vector<Point4>> rebuilt(const Triangulation& t) {
  Triangulation fresh;
  const auto& st = t.store();
  for (VertexId v = 1; v < st.vertex_slots(); ++v)
    if (st.vertex(v).kind != VertexKind::removed && st.vertex(v).cell != kNoCell)
      fresh.insert(st.point(v), st.vertex(v).kind);
  return cells_by_points(fresh);
}

TEST(TriangulationRemove, RandomInsertRemoveSequenceValidAfterEveryOperation) {
  const HoleCounters at_start = hole_counters();
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
    EXPECT_EQ(cells_by_points(t), rebuilt(t)) << "seed " << seed;
  }
  // Random points are in general position: every hole is gift-wrapped and proven so.
  const std::uint64_t holes = hole_counters().holes - at_start.holes;
  EXPECT_GT(holes, 150u);
  EXPECT_EQ(hole_counters().fallbacks - at_start.fallbacks, 0u) << "of " << holes << " holes";
}

TEST(TriangulationRemove, LatticeRemovalsStayValid) {
  // Removing from a lattice leaves co-spherical link vertices: the tie-break must glue the hole,
  // and give the triangulation that building the remaining points afresh gives.
  for (int k : {4, 5}) {
    Triangulation t;
    for (const Point4& p : lattice(k)) t.insert(p);  // in order: rebuilt() repeats it
    std::mt19937_64 rng(8);
    const HoleCounters before = hole_counters();
    for (int r = 0; r < 12; ++r) {
      const auto candidates = interior_vertices(t);
      if (candidates.empty()) break;
      ASSERT_TRUE(t.remove(candidates[rng() % candidates.size()]));
      const CheckResult check = check_triangulation(t);
      ASSERT_TRUE(check.ok) << "lattice " << k << " removal " << r << ": " << check.error;
    }
    EXPECT_EQ(cells_by_points(t), rebuilt(t)) << "lattice " << k;
    std::printf("lattice %d: %llu holes, %llu left to the link triangulation\n", k,
                static_cast<unsigned long long>(hole_counters().holes - before.holes),
                static_cast<unsigned long long>(hole_counters().fallbacks - before.fallbacks));
  }
}

TEST(TriangulationRemove, LinkTriangulationFillsTheSameHoles) {
  // The fallback of the gift-wrapping: with wrapping off, the same removals give the same
  // triangulation, on random points and on a lattice.
  for (bool on_lattice : {false, true}) {
    std::set<std::vector<Point4>> result[2];
    for (bool wrap : {true, false}) {
      hole_counters().wrap = wrap;
      const HoleCounters before = hole_counters();
      Triangulation t;
      for (const Point4& p : on_lattice ? lattice(5) : random_points(300, 21)) t.insert(p);
      std::mt19937_64 rng(5);
      for (int r = 0; r < 20; ++r) {
        const auto candidates = interior_vertices(t);
        ASSERT_FALSE(candidates.empty());
        ASSERT_TRUE(t.remove(candidates[rng() % candidates.size()]));
      }
      ASSERT_TRUE(check_triangulation(t).ok);
      EXPECT_EQ(hole_counters().fallbacks - before.fallbacks, wrap ? 0u : 20u);
      result[wrap] = cells_by_points(t);
    }
    hole_counters().wrap = true;
    EXPECT_EQ(result[0], result[1]) << (on_lattice ? "lattice" : "random points");
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
