#include "refine/manifold_relabeling.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>

#include "support/parallel_parts.h"

namespace mesh4d::refine {

using delaunay::CellId;
using mesh4d::VertexId;

namespace {

// Passes over the failing pairs; on the patients the count stops falling after three or four.
constexpr int kRounds = 8;
// Vertices per thread, at least, when a round's links are looked at again on the job's threads.
constexpr std::size_t kCheckShare = 64;
// Failing pairs per thread, at least, when their repairs run side by side (a repair takes a
// few tenths of a millisecond, a thread's start some tens of microseconds).
constexpr std::size_t kPairsPerThread = 2;
// Colours of failing pairs whose repairs run side by side (one bit each per vertex).
constexpr int kColours = 64;

// By vertex then label, each once: in periodic time a vertex and its twin stand for the same
// pair (counted_vertex); in open time the lists are in this order already.
void distinct_pairs(std::vector<NonManifoldVertex>& pairs) {
  const auto key = [](const NonManifoldVertex& f) { return std::pair(f.vertex, f.label); };
  std::stable_sort(pairs.begin(), pairs.end(),
                   [&](const auto& a, const auto& b) { return key(a) < key(b); });
  pairs.erase(std::unique(pairs.begin(), pairs.end(),
                          [&](const auto& a, const auto& b) { return key(a) == key(b); }),
              pairs.end());
}

}  // namespace

std::size_t ManifoldRelabeling::repair_all(const std::vector<NonManifoldVertex>& due,
                                           std::vector<VertexId>& touched) {
  const unsigned threads = working_threads(state_.params);
  // Alone, in order: on one thread, and while piece matching guards a cut (its guard walks the
  // whole region).
  if (threads <= 1 || repair_.guarded() || due.size() < 2 * kPairsPerThread) {
    for (const NonManifoldVertex& f : due) repair_.repair(f);
    const std::vector<VertexId> t = repair_.take_touched();
    touched.insert(touched.end(), t.begin(), t.end());
    return repair_.take_moved();
  }
  // Side by side: the pairs take colours in their order, each the first that no earlier pair
  // whose claim (RepairClaims) meets its own has taken; one colour's pairs are repaired at once
  // (none reads or writes what another writes), one colour after the other. The order depends
  // on the pairs alone, so the labels are the same on any number of threads above one. (On one
  // thread the pairs go in their own order: the sequential meshes.) Pairs left when every
  // colour is taken go round again.
  std::vector<std::vector<VertexId>> claims(due.size());
  const unsigned claim_parts = support::parts_for(due.size(), kPairsPerThread, threads);
  support::run_parts(claim_parts, [&](unsigned part) {
    RepairClaims claimer(state_);
    const auto [begin, end] = support::part_range(due.size(), part, claim_parts);
    for (std::size_t i = begin; i < end; ++i) claimer.claim(due[i].vertex, claims[i]);
  });
  while (repairers_.size() < threads) repairers_.emplace_back(state_, scan_);
  std::vector<std::size_t> waiting(due.size()), later;
  for (std::size_t i = 0; i < due.size(); ++i) waiting[i] = i;
  std::array<std::vector<std::size_t>, kColours> colours;
  while (!waiting.empty()) {
    colours_.assign(state_.tri.store().vertex_slots(), 0);
    for (auto& c : colours) c.clear();
    later.clear();
    for (std::size_t i : waiting) {
      std::uint64_t taken = 0;
      for (VertexId u : claims[i]) taken |= colours_[u];
      if (~taken == 0) {
        later.push_back(i);
        continue;
      }
      const int colour = std::countr_one(taken);
      colours[colour].push_back(i);
      for (VertexId u : claims[i]) colours_[u] |= std::uint64_t{1} << colour;
    }
    for (const std::vector<std::size_t>& batch : colours) {
      const unsigned parts = support::parts_for(batch.size(), kPairsPerThread, threads);
      std::atomic<std::size_t> next{0};
      support::run_parts(parts, [&](unsigned part) {
        for (std::size_t k; (k = next.fetch_add(1, std::memory_order_relaxed)) < batch.size();)
          repairers_[part].repair(due[batch[k]]);
      });
    }
    waiting.swap(later);
  }
  std::size_t moved = 0;
  for (LinkRepair& r : repairers_) {
    moved += r.take_moved();
    const std::vector<VertexId> t = r.take_touched();
    touched.insert(touched.end(), t.begin(), t.end());
  }
  return moved;
}

ManifoldRelabeling::Outcome ManifoldRelabeling::run(const std::vector<VertexId>* around) {
  Outcome outcome;
  std::vector<NonManifoldVertex> failing;
  if (around) {
    std::vector<CellId> star;
    for (VertexId v : *around)
      if (state_.tri.store().vertex(v).kind != delaunay::VertexKind::removed)
        non_manifold_labels_at(state_, v, star, &failing);
  } else {
    failing = find_non_manifold_vertices(state_);
  }
  distinct_pairs(failing);
  std::vector<VertexId> retry;    // vertices near this round's moves
  std::vector<VertexId> touched;  // vertices of the pentatopes moved this round
  std::vector<NonManifoldVertex> due;
  for (int round = 0; round < kRounds && !failing.empty(); ++round) {
    due.clear();
    for (const NonManifoldVertex& f : failing)
      if (round == 0 || std::binary_search(retry.begin(), retry.end(), f.vertex)) due.push_back(f);
    const std::size_t moved = repair_all(due, touched);
    outcome.moved += moved;
    // Only the moved pentatopes' vertices have new links: they and the failing ones are looked
    // at again, not the whole boundary. A pair that found no move is tried again only where a
    // move changed a star it reads (its vertex's star holds the moved pentatope's vertices).
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    std::vector<VertexId> look = touched;
    for (const NonManifoldVertex& f : failing) look.push_back(f.vertex);
    std::sort(look.begin(), look.end());
    look.erase(std::unique(look.begin(), look.end()), look.end());
    // (Read only: on the job's threads, each a contiguous share, joined in order.)
    const unsigned parts =
        support::parts_for(look.size(), kCheckShare, working_threads(state_.params));
    std::vector<std::vector<NonManifoldVertex>> found(parts);
    std::vector<std::vector<VertexId>> near(parts);
    support::run_parts(parts, [&](unsigned part) {
      std::vector<CellId> star;
      const auto [begin, end] = support::part_range(look.size(), part, parts);
      for (std::size_t i = begin; i < end; ++i) {
        const VertexId v = look[i];
        non_manifold_labels_at(state_, v, star, &found[part]);
        if (std::binary_search(touched.begin(), touched.end(), v))
          for (CellId c : star)
            for (VertexId u : state_.tri.store().cell(c).v) near[part].push_back(u);
      }
    });
    failing.clear();
    retry.clear();
    for (unsigned part = 0; part < parts; ++part) {
      failing.insert(failing.end(), found[part].begin(), found[part].end());
      retry.insert(retry.end(), near[part].begin(), near[part].end());
    }
    distinct_pairs(failing);
    std::sort(retry.begin(), retry.end());
    retry.erase(std::unique(retry.begin(), retry.end()), retry.end());
    touched.clear();
    if (moved == 0) break;
  }
  repair_.forget_all();
  for (LinkRepair& r : repairers_) r.forget_all();
  outcome.failing = std::move(failing);
  return outcome;
}

}  // namespace mesh4d::refine
