#include "refine/manifold_scan.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <utility>

#include "mesh/link_topology.h"
#include "support/parallel_parts.h"

namespace mesh4d::refine {

using delaunay::CellId;
using domain::Label;
using mesh4d::VertexId;

namespace {

constexpr std::size_t kScanPerThread = 4096;                   // vertices; fewer stay on one thread
constexpr std::size_t kCellsPerThread = std::size_t{1} << 16;  // pentatope slots, likewise
constexpr std::size_t kLoadsAhead = 8;                         // star pentatopes, prefetched

}  // namespace

void region_link(const RefinementState& state, VertexId v, std::span<const CellId> star, Label l,
                 std::vector<std::array<std::uint32_t, 3>>& link, std::size_t* inside_count) {
  const auto& st = state.tri.store();
  link.clear();
  std::size_t inside = 0;
  for (CellId c : star) {
    if (state.output_label(c) != l) continue;
    ++inside;
    const auto& cell = st.cell(c);
    for (int f = 0; f < 5; ++f) {
      if (cell.v[f] == v || state.output_label(cell.n[f]) == l) continue;
      std::array<std::uint32_t, 3> t;
      for (int q = 0, m = 0; q < 5; ++q)
        if (q != f && cell.v[q] != v) t[m++] = cell.v[q];
      std::sort(t.begin(), t.end());
      link.push_back(t);
    }
  }
  *inside_count = inside;
}

bool region_link_fails(const RefinementState& state, VertexId v, std::span<const CellId> star,
                       Label l) {
  if (!state.output_region(l)) return false;
  thread_local std::vector<std::array<std::uint32_t, 3>> link;
  std::size_t inside = 0;
  region_link(state, v, star, l, link, &inside);
  if (inside == 0 || inside == star.size()) return false;
  return !mesh::link_is_sphere(link);
}

std::vector<VertexId> link_trouble(const RefinementState& state, VertexId v,
                                   std::span<const CellId> star, Label l) {
  std::vector<std::array<std::uint32_t, 3>> link;
  std::size_t inside = 0;
  region_link(state, v, star, l, link, &inside);
  // (w, the edge opposite w) for every corner of every triangle, grouped by w.
  std::vector<std::pair<VertexId, std::array<std::uint32_t, 2>>> around;
  for (const auto& [a, b, c] : link) {
    around.push_back({a, {b, c}});
    around.push_back({b, {a, c}});
    around.push_back({c, {a, b}});
  }
  std::sort(around.begin(), around.end());
  std::vector<VertexId> trouble;
  std::vector<std::array<std::uint32_t, 2>> umbrella;
  for (std::size_t i = 0; i < around.size();) {
    std::size_t j = i;
    umbrella.clear();
    for (; j < around.size() && around[j].first == around[i].first; ++j)
      umbrella.push_back(around[j].second);
    if (!mesh::link_is_circle(umbrella)) trouble.push_back(around[i].first);
    i = j;
  }
  return trouble;
}

namespace {

// Appends the failing labels at v, whose star is given.
void failing_labels(const RefinementState& state, VertexId v, std::span<const CellId> star,
                    std::vector<NonManifoldVertex>* out) {
  const std::size_t first = out->size();
  // The star's labels (a handful; any number is taken).
  thread_local std::vector<Label> seen;
  seen.clear();
  const auto& st = state.tri.store();
  for (std::size_t i = 0; i < star.size(); ++i) {
    // The star's pentatopes lie anywhere in memory: their infos are loaded a few steps ahead,
    // and their vertices now for region_link, which reads them next (most of the scan's time
    // was these loads).
    if (i + kLoadsAhead < star.size()) __builtin_prefetch(&state.info[star[i + kLoadsAhead]]);
    __builtin_prefetch(&st.cell(star[i]));
    const Label l = state.output_label(star[i]);
    if (std::find(seen.begin(), seen.end(), l) == seen.end()) seen.push_back(l);
  }
  const std::size_t count = seen.size();
  // Two labels only: each one's part of the link (a 3-sphere) is the other's complement, with
  // the same boundary surface, so one test answers for both.
  if (count == 2 && state.output_region(seen[0]) && state.output_region(seen[1])) {
    if (region_link_fails(state, v, star, seen[0]))
      for (int k = 0; k < 2; ++k) out->push_back({v, seen[k]});
  } else {
    for (std::size_t k = 0; k < count; ++k)
      if (region_link_fails(state, v, star, seen[k])) out->push_back({v, seen[k]});
  }
  std::sort(
      out->begin() + static_cast<std::ptrdiff_t>(first), out->end(),
      [](const NonManifoldVertex& a, const NonManifoldVertex& b) { return a.label < b.label; });
}

}  // namespace

VertexId counted_vertex(const RefinementState& state, VertexId v) {
  if (!state.covering.active() || v == delaunay::kInfiniteVertex) return v;
  const double t = state.tri.store().point(v)[3];
  if (state.covering.in_middle(t)) return v;
  const domain::TimePeriod& period = state.covering.period();
  const int periods = static_cast<int>(std::floor((t - period.start) / period.length));
  return state.covering.twin(state.tri, v, -periods);
}

void non_manifold_labels_at(const RefinementState& state, VertexId v, std::vector<CellId>& star,
                            std::vector<NonManifoldVertex>* out) {
  v = counted_vertex(state, v);
  star.clear();
  if (v == delaunay::kNoVertex) return;
  state.tri.incident_cells(v, star);
  failing_labels(state, v, star, out);
}

std::vector<NonManifoldVertex> find_non_manifold_vertices(const RefinementState& state) {
  // The boundary vertices (those of a pentatope with a neighbor of another label), then their
  // stars from passes over the pentatopes (a counting sort: a star search per vertex cost three
  // times as much), each pass on the job's threads, each star in pentatope order.
  const auto& st = state.tri.store();
  const std::size_t slots = st.cell_slots();
  const unsigned threads = working_threads(state.params);
  const unsigned cell_parts = support::parts_for(slots, kCellsPerThread, threads);
  const auto over_part = [&](unsigned part, auto fn) {
    const auto [begin, end] = support::part_range(slots, part, cell_parts);
    for (std::size_t c = begin; c < end; ++c)
      if (st.is_live(static_cast<CellId>(c))) fn(static_cast<CellId>(c));
  };
  const auto over_cells = [&](auto fn) {
    support::run_parts(cell_parts, [&](unsigned part) { over_part(part, fn); });
  };
  std::vector<std::uint8_t> marked(st.vertex_slots(), 0);
  over_cells([&](CellId c) {
    const Label l = state.output_label(c);
    if (!state.output_region(l)) return;
    const auto& cell = st.cell(c);
    for (int f = 0; f < 5; ++f)
      if (state.output_label(cell.n[f]) != l) {
        // (Read first: most are marked already, and a store would take the line from the other
        // threads.)
        for (VertexId v : cell.v)
          if (std::atomic_ref a(marked[v]); !a.load(std::memory_order_relaxed))
            a.store(1, std::memory_order_relaxed);
        break;
      }
  });
  std::vector<VertexId> boundary;
  // In periodic time the middle sheet's vertices stand for all: their links are the glued
  // mesh's (the labels are the same in every sheet).
  for (VertexId v = 0; v < st.vertex_slots(); ++v)
    if (marked[v] && state.covering.counts(st.point(v)[3]))
      boundary.push_back(v);
    else
      marked[v] = 0;
  // Each part counts its pentatopes per vertex, then writes them at its own offsets: no
  // counter is shared (atomic counters cost more on two threads than the pass on one), and
  // every star is in pentatope order, as on one thread.
  const std::size_t vertex_slots = st.vertex_slots();
  std::vector<std::vector<std::uint32_t>> counts(cell_parts,
                                                 std::vector<std::uint32_t>(vertex_slots, 0));
  support::run_parts(cell_parts, [&](unsigned part) {
    std::vector<std::uint32_t>& count = counts[part];
    over_part(part, [&](CellId c) {
      for (VertexId v : st.cell(c).v)
        if (marked[v]) ++count[v];
    });
  });
  // first[v]: where v's star starts; counts[part][v] becomes where the part's share of it does.
  std::vector<std::uint32_t> first(vertex_slots + 1, 0);
  for (std::size_t v = 0; v < vertex_slots; ++v) {
    std::uint32_t at = first[v];
    for (unsigned part = 0; part < cell_parts; ++part) at += std::exchange(counts[part][v], at);
    first[v + 1] = at;
  }
  std::vector<CellId> stars(first.back());
  support::run_parts(cell_parts, [&](unsigned part) {
    std::vector<std::uint32_t>& next = counts[part];
    over_part(part, [&](CellId c) {
      for (VertexId v : st.cell(c).v)
        if (marked[v]) stars[next[v]++] = c;
    });
  });

  const unsigned parts = static_cast<unsigned>(std::min<std::size_t>(
      working_threads(state.params), std::max<std::size_t>(1, boundary.size() / kScanPerThread)));
  std::vector<std::vector<NonManifoldVertex>> found(parts);
  support::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = support::part_range(boundary.size(), part, parts);
    for (std::size_t i = begin; i < end; ++i) {
      const VertexId v = boundary[i];
      failing_labels(state, v, std::span(stars).subspan(first[v], first[v + 1] - first[v]),
                     &found[part]);
    }
  });
  std::vector<NonManifoldVertex> all;
  for (auto& f : found) all.insert(all.end(), f.begin(), f.end());
  return all;
}

std::vector<NonManifoldVertex> failing_pairs_at(const RefinementState& state,
                                                const std::vector<VertexId>& vertices) {
  std::vector<NonManifoldVertex> failing;
  std::vector<CellId> star;
  for (VertexId v : vertices)
    if (state.tri.store().vertex(v).kind != delaunay::VertexKind::removed)
      non_manifold_labels_at(state, v, star, &failing);
  return failing;
}

void distinct_pairs(std::vector<NonManifoldVertex>& pairs) {
  const auto key = [](const NonManifoldVertex& f) { return std::pair(f.vertex, f.label); };
  std::stable_sort(pairs.begin(), pairs.end(),
                   [&](const auto& a, const auto& b) { return key(a) < key(b); });
  pairs.erase(std::unique(pairs.begin(), pairs.end(),
                          [&](const auto& a, const auto& b) { return key(a) == key(b); }),
              pairs.end());
}

}  // namespace mesh4d::refine
