// The manifold step's repairs run side by side on the job's threads only where two repairs cannot
// see each other's moves (link_repair.h, repair_claim): the labels it leaves are the same on any
// number of threads as on one, where the repairs run in order. A triangulation of random feature
// points labeled by the ventricle, with one pentatope in a hundred given another label, fails its
// links at hundreds of vertices all over the box.
#include "refine/manifold_relabeling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <random>
#include <tuple>
#include <vector>

#include "domain/surface_oracle.h"
#include "refine/pinch_scan.h"
#include "refine/refine_checks.h"
#include "refine/refinement_state.h"

namespace mesh4d::refine {
namespace {

using delaunay::CellId;
using domain::Label;

struct Relabeled {
  std::vector<Label> labels;  // per pentatope slot (0 where not live or not finite)
  std::size_t moved = 0;
  std::vector<std::pair<VertexId, Label>> failing_before, failing_after;
};

std::vector<std::pair<VertexId, Label>> pairs_of(const std::vector<NonManifoldVertex>& v) {
  std::vector<std::pair<VertexId, Label>> out;
  for (const NonManifoldVertex& f : v) out.push_back({f.vertex, f.label});
  return out;
}

// A triangulation of random feature points in the ventricle's box, its pentatopes labeled by
// the image and one in a hundred given another label: the same each time (a fixed seed).
void build_noisy_ventricle(RefinementState& state, int points = 6000) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  const std::array<Point4, 2> bounds = state.oracle.image().bounds();
  for (int i = 0; i < points; ++i) {
    Point4 p;
    for (int k = 0; k < 4; ++k)
      p[k] = bounds[0][k] + (0.1 + 0.8 * unit(rng)) * (bounds[1][k] - bounds[0][k]);
    state.tri.insert(p, delaunay::VertexKind::feature);
  }
  const auto& st = state.tri.store();
  std::vector<CellId> live;
  for (CellId c = 0; c < st.cell_slots(); ++c)
    if (st.is_live(c)) live.push_back(c);
  state.admit(live);
  for (CellId c : live)
    if (state.info[c].finite && unit(rng) < 0.003)
      state.set_label(c, static_cast<Label>((state.label_of(c) + 1 + (unit(rng) < 0.5)) % 3));
}

RefineParams noisy_params(unsigned threads) {
  RefineParams params;
  params.delta = 6;  // the moves' new facets may lie 3 from ∂Ω: most of the box's are that near
  params.threads = threads;
  return params;
}

std::vector<Label> labels_of(const RefinementState& state) {
  const auto& st = state.tri.store();
  std::vector<Label> out(st.cell_slots(), 0);
  for (CellId c = 0; c < st.cell_slots(); ++c)
    if (st.is_live(c)) out[c] = state.output_label(c);
  return out;
}

std::size_t differences(const std::vector<Label>& a, const std::vector<Label>& b) {
  std::size_t n = 0;
  for (std::size_t c = 0; c < a.size(); ++c) n += a[c] != b[c];
  return n;
}

// The manifold step on `threads`.
Relabeled relabel_noisy_ventricle(const domain::SurfaceOracle& oracle, unsigned threads) {
  RefinementState state(oracle, noisy_params(threads));
  build_noisy_ventricle(state);
  PinchScan scan(state);
  Relabeled out;
  out.failing_before = pairs_of(find_non_manifold_vertices(state));
  ManifoldRelabeling step(state, scan);
  const ManifoldRelabeling::Outcome r = step.run();
  out.moved = r.moved;
  out.failing_after = pairs_of(r.failing);
  out.labels = labels_of(state);
  return out;
}

// What lets repairs run side by side: failing pairs whose claims share no vertex give the same
// labels repaired in either order. The pairs are split into sets of such pairs (each in the
// first set whose claims its own meets none of, as the manifold step colours them), and each
// set is repaired first to last on one copy of the triangulation and last to first on another.
TEST(RepairClaims, RepairsWhoseClaimsAreApartGiveTheSameLabelsInEitherOrder) {
  const domain::LabelImage4 image = small_ventricle();
  const domain::SurfaceOracle oracle(image);
  RefinementState forward(oracle, noisy_params(1)), backward(oracle, noisy_params(1));
  build_noisy_ventricle(forward);
  build_noisy_ventricle(backward);
  const std::vector<NonManifoldVertex> failing = find_non_manifold_vertices(forward);
  RepairClaims claims(forward);
  std::vector<std::vector<NonManifoldVertex>> sets;
  std::vector<std::vector<char>> held;  // per set, per vertex: in a claim of the set
  std::vector<VertexId> claim;
  for (const NonManifoldVertex& f : failing) {
    claims.claim(f.vertex, claim);
    std::size_t s = 0;
    while (s < sets.size() &&
           std::any_of(claim.begin(), claim.end(), [&](VertexId u) { return held[s][u]; }))
      ++s;
    if (s == sets.size())
      sets.emplace_back(), held.emplace_back(forward.tri.store().vertex_slots());
    sets[s].push_back(f);
    for (VertexId u : claim) held[s][u] = 1;
  }
  PinchScan forward_scan(forward), backward_scan(backward);
  LinkRepair forward_repair(forward, forward_scan), backward_repair(backward, backward_scan);
  std::size_t reordered = 0;  // pairs in a set with others
  for (const auto& set : sets) {
    if (set.size() > 1) reordered += set.size();
    for (const NonManifoldVertex& f : set) forward_repair.repair(f);
    for (auto f = set.rbegin(); f != set.rend(); ++f) backward_repair.repair(*f);
  }
  const std::size_t moved = forward_repair.take_moved();
  std::printf(
      "%zu failing pairs in %zu sets, %zu of them in a set with others; %zu pentatopes "
      "moved\n",
      failing.size(), sets.size(), reordered, moved);
  ASSERT_GT(reordered, 200u) << "too few pairs to reorder";
  ASSERT_GT(moved, 100u);
  EXPECT_EQ(backward_repair.take_moved(), moved);
  EXPECT_EQ(differences(labels_of(forward), labels_of(backward)), 0u);
}

TEST(ManifoldRelabeling, OnThreadsTheRepairsLeaveTheSameLabelsOnAnyNumberOfThreads) {
  const domain::LabelImage4 image = small_ventricle();
  const domain::SurfaceOracle oracle(image);
  const Relabeled one = relabel_noisy_ventricle(oracle, 1);
  const Relabeled two = relabel_noisy_ventricle(oracle, 2);
  std::printf(
      "noisy ventricle: %zu failing pairs; one thread %zu moved, %zu left; "
      "two threads %zu moved, %zu left\n",
      one.failing_before.size(), one.moved, one.failing_after.size(), two.moved,
      two.failing_after.size());
  ASSERT_GT(one.failing_before.size(), 200u) << "too few failing links to repair side by side";
  EXPECT_EQ(two.failing_before, one.failing_before);
  ASSERT_GT(two.moved, 100u);
  ASSERT_LT(two.failing_after.size(), two.failing_before.size());
  for (unsigned threads : {4u}) {
    const Relabeled many = relabel_noisy_ventricle(oracle, threads);
    EXPECT_EQ(many.moved, two.moved) << threads << " threads";
    EXPECT_EQ(many.failing_after, two.failing_after) << threads << " threads";
    EXPECT_EQ(differences(two.labels, many.labels), 0u)
        << threads << " threads: pentatopes labeled otherwise than on two";
  }
}

}  // namespace
}  // namespace mesh4d::refine
