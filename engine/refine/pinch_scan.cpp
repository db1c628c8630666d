#include "refine/pinch_scan.h"

#include <algorithm>
#include <iterator>
#include <tuple>

#include "delaunay/facet_key.h"
#include "support/parallel_parts.h"

namespace mesh4d::refine {

using delaunay::CellId;
using domain::Label;
using mesh4d::VertexId;

namespace {

// Scans shorter than this stay on one thread: starting threads would cost more.
constexpr std::size_t kScanPerThread = 4096;
constexpr CellId kLoadsAhead = 8;  // pentatopes or records, prefetched ahead of use

// The part that counts a triangle: every record of one triangle meets in one part.
unsigned bucket_of(std::uint64_t hash, unsigned parts) {
  return static_cast<unsigned>((hash >> 40) % parts);
}

// Size of an open-addressing table for the items that the parts handed to `part`: a power of
// two, at least twice their number.
template <class T>
std::size_t table_size(const std::vector<std::vector<std::vector<T>>>& handed, unsigned part) {
  std::size_t n = 0;
  for (const auto& from : handed) n += from[part].size();
  std::size_t size = 16;
  while (size < 2 * n) size *= 2;
  return size;
}

}  // namespace

unsigned PinchScan::scan_parts(std::size_t items) const {
  const std::size_t useful = std::max<std::size_t>(1, items / kScanPerThread);
  return static_cast<unsigned>(std::min<std::size_t>(working_threads(state_.params), useful));
}

std::size_t PinchScan::count(std::vector<PinchedTriangle>* pinched, PinchCounts* counts,
                             bool only_if_pinched) const {
  // Records (region label, sorted triangle, facet) for every triangle of every region's
  // boundary facet. With several threads, each scans a range of pentatopes and hands each
  // record to the part its triangle hashes to; each part then counts its own triangles.
  struct Record {
    std::array<std::uint32_t, 4> key;  // label, then the triangle's vertices
    std::uint64_t hash;
    CellId cell;
    int facet;
  };
  const auto& st = state_.tri.store();
  const bool periodic = state_.covering.active();
  const unsigned parts = scan_parts(st.cell_slots());
  std::vector<std::vector<std::vector<Record>>> records(parts,
                                                        std::vector<std::vector<Record>>(parts));
  support::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = support::part_range(st.cell_slots(), part, parts);
    for (CellId c = static_cast<CellId>(begin); c < end; ++c) {
      // The neighbors' infos lie anywhere in memory: a pentatope a few slots on has its
      // neighbors' loads started now (the pentatopes themselves come in memory order).
      if (c + kLoadsAhead < end && st.is_live(c + kLoadsAhead))
        for (CellId n : st.cell(c + kLoadsAhead).n) __builtin_prefetch(&state_.info[n]);
      if (!st.is_live(c) || !state_.info[c].finite) continue;
      const domain::Label own = state_.label_of(c);  // read once: up to 21 uses below
      if (!state_.output_region(own)) continue;
      const auto& cell = st.cell(c);
      // In periodic time a triangle counts where its lowest vertex is in the middle sheet: a
      // pentatope with no vertex there has none (most of the margins' pentatopes).
      if (periodic && std::none_of(std::begin(cell.v), std::end(cell.v), [&](VertexId v) {
            return state_.covering.in_middle(st.point(v)[3]);
          }))
        continue;
      for (int i = 0; i < 5; ++i) {
        const CellId n = cell.n[i];
        const domain::Label other = state_.output_label(n);
        if (other == own) continue;
        const delaunay::FacetKey facet = delaunay::facet_key(cell.v, i);
        for (int skip = 0; skip < 4; ++skip) {
          Record r{{own, 0, 0, 0}, 0, c, i};
          for (int k = 0, m = 1; k < 4; ++k)
            if (k != skip) r.key[m++] = facet[k];
          if (periodic && !counts_triangle({r.key[1], r.key[2], r.key[3]})) continue;
          r.hash = hash_key(r.key[0], r.key[1], r.key[2], r.key[3]);
          records[part][bucket_of(r.hash, parts)].push_back(r);
        }
      }
    }
  });
  // Count each triangle's facets in an open-addressing table (a sort of all records cost a
  // fifth of the ventricle's refinement, as the repair recounts after every round).
  struct Slot {
    std::array<std::uint32_t, 4> key;
    std::uint32_t count = 0;
    std::uint32_t pinch = 0;  // 1 + index in found[part], once listed
  };
  std::vector<std::vector<Slot>> tables(counts ? parts : 0);
  std::vector<std::size_t> pinches(parts, 0);
  std::vector<std::vector<PinchedTriangle>> found(parts);
  support::run_parts(parts, [&](unsigned part) {
    const std::size_t size = table_size(records, part);
    std::vector<Slot> table(size);
    const auto slot_of = [&](const Record& r) -> Slot& {
      for (std::size_t i = r.hash & (size - 1);; i = (i + 1) & (size - 1))
        if (table[i].count == 0 || table[i].key == r.key) return table[i];
    };
    for (const auto& from : records) {
      const std::vector<Record>& mine = from[part];
      for (std::size_t k = 0; k < mine.size(); ++k) {
        // Each record's slot is a random place in the table: loaded a few records ahead.
        if (k + kLoadsAhead < mine.size())
          __builtin_prefetch(&table[mine[k + kLoadsAhead].hash & (size - 1)]);
        Slot& slot = slot_of(mine[k]);
        slot.key = mine[k].key;
        if (++slot.count == 3) ++pinches[part];
      }
    }
    if (pinched && pinches[part] > 0)
      for (const auto& from : records)
        for (const Record& r : from[part]) {
          Slot& slot = slot_of(r);
          if (slot.count <= 2) continue;
          if (slot.pinch == 0) {
            found[part].emplace_back();
            found[part].back().triangle = {r.key[1], r.key[2], r.key[3]};
            slot.pinch = static_cast<std::uint32_t>(found[part].size());
          }
          found[part][slot.pinch - 1].facets.emplace_back(r.cell, r.facet);
        }
    if (counts) tables[part] = std::move(table);
  });
  std::size_t pinch_total = 0;
  for (unsigned part = 0; part < parts; ++part) pinch_total += pinches[part];
  if (counts && (pinch_total > 0 || !only_if_pinched)) {
    // The records go first: at the first count of the repair this is its largest moment.
    records = {};
    std::size_t keys = 0;
    for (const auto& table : tables)
      for (const Slot& slot : table) keys += slot.count > 0;
    counts->reserve(keys);
    for (auto& table : tables) {
      for (const Slot& slot : table)
        if (slot.count > 0) counts->add(slot.key, static_cast<int>(slot.count));
      table = {};
    }
  }
  std::size_t total = 0;
  for (unsigned part = 0; part < parts; ++part) {
    total += pinches[part];
    if (pinched)
      pinched->insert(pinched->end(), std::make_move_iterator(found[part].begin()),
                      std::make_move_iterator(found[part].end()));
  }
  return total;
}

void PinchScan::link_cycle(CellId start, const std::array<VertexId, 3>& t,
                           std::vector<CellId>& cycle, std::vector<int>& crossed) const {
  // The link of a triangle in a 4D triangulation is a circle: each pentatope around it has two
  // facets through it (opposite its two other vertices), one shared with each neighbor on the
  // cycle. Crossing, each time, the facet opposite the other vertex shared with the previous
  // pentatope walks the cycle.
  const auto& st = state_.tri.store();
  const auto in_t = [&](VertexId v) { return v == t[0] || v == t[1] || v == t[2]; };
  cycle.clear();
  crossed.clear();
  CellId cur = start;
  VertexId cross = delaunay::kNoVertex;
  for (int k = 0; k < 5; ++k)
    if (!in_t(st.cell(cur).v[k])) {
      cross = st.cell(cur).v[k];
      break;
    }
  for (int guard = 0; guard < 100000; ++guard) {
    const auto& cell = st.cell(cur);
    int i = 0, other = -1;
    for (int k = 0; k < 5; ++k) {
      if (cell.v[k] == cross)
        i = k;
      else if (!in_t(cell.v[k]))
        other = k;
    }
    cycle.push_back(cur);
    crossed.push_back(i);
    cross = cell.v[other];
    cur = cell.n[i];
    if (cur == start) break;
  }
}

void PinchScan::pinches_at(CellId start, const std::array<VertexId, 3>& t,
                           std::vector<PinchedTriangle>* pinched) const {
  // A region's boundary facets at t are its label changes along the cycle around t. Asked for
  // every triangle the repair's recount looks at, nearly all unpinched: the cycle and its
  // labels go into reused scratch, and a label's facets are listed only when it has more than
  // two of them.
  const auto& st = state_.tri.store();
  thread_local std::vector<CellId> cycle;
  thread_local std::vector<int> crossed;  // facet of cycle[i] shared with cycle[i + 1]
  thread_local std::vector<domain::Label> labels, distinct;
  link_cycle(start, t, cycle, crossed);
  const std::size_t n = cycle.size();
  labels.resize(n);
  distinct.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const domain::Label l = labels[i] = state_.output_label(cycle[i]);
    if (state_.output_region(l) && std::find(distinct.begin(), distinct.end(), l) == distinct.end())
      distinct.push_back(l);
  }
  for (const domain::Label l : distinct) {
    int changes = 0;
    for (std::size_t i = 0; i < n; ++i) changes += (labels[i] == l) != (labels[(i + 1) % n] == l);
    if (changes <= 2) continue;
    PinchedTriangle p{t, {}};
    for (std::size_t i = 0; i < n; ++i) {
      const CellId a = cycle[i], b = cycle[(i + 1) % n];
      const bool a_in = labels[i] == l, b_in = labels[(i + 1) % n] == l;
      if (a_in == b_in) continue;
      if (a_in) {
        p.facets.emplace_back(a, crossed[i]);
      } else {
        int back = 0;
        while (st.cell(b).n[back] != a) ++back;
        p.facets.emplace_back(b, back);
      }
    }
    pinched->push_back(std::move(p));
  }
}

bool PinchScan::counts_triangle(const Triangle& t) const {
  if (!state_.covering.active()) return true;
  const auto& st = state_.tri.store();
  double lowest = st.point(t[0])[3];
  for (VertexId v : t) lowest = std::min(lowest, st.point(v)[3]);
  return state_.covering.counts(lowest);
}

std::array<Triangle, 10> triangles_of(const mesh4d::VertexId (&vertices)[5]) {
  std::array<mesh4d::VertexId, 5> v;
  std::copy_n(vertices, 5, v.begin());
  std::sort(v.begin(), v.end());
  std::array<Triangle, 10> out;
  int k = 0;
  for (int a = 0; a < 5; ++a)
    for (int b = a + 1; b < 5; ++b)
      for (int d = b + 1; d < 5; ++d) out[k++] = {v[a], v[b], v[d]};
  return out;
}

std::vector<PinchedTriangle> PinchScan::pinches_on(const std::vector<CellId>& cells) const {
  std::vector<std::pair<Triangle, CellId>> triangles;
  for (CellId c : cells)
    for (const Triangle& t : triangles_of(state_.tri.store().cell(c).v))
      triangles.push_back({t, c});
  std::sort(triangles.begin(), triangles.end());
  std::vector<PinchedTriangle> pinched;
  for (std::size_t i = 0; i < triangles.size(); ++i)
    if (i == 0 || triangles[i].first != triangles[i - 1].first)
      pinches_at(triangles[i].second, triangles[i].first, &pinched);
  return pinched;
}

void PinchScan::sort_canonically(std::vector<PinchedTriangle>& pinches) const {
  // Every facet of a pinch lies in a pentatope of the pinched region: its label is the pinch's.
  for (PinchedTriangle& p : pinches) std::sort(p.facets.begin(), p.facets.end());
  std::sort(pinches.begin(), pinches.end(),
            [&](const PinchedTriangle& a, const PinchedTriangle& b) {
              const Label la = state_.label_of(a.facets.front().first),
                          lb = state_.label_of(b.facets.front().first);
              return a.triangle != b.triangle ? a.triangle < b.triangle : la < lb;
            });
}

}  // namespace mesh4d::refine
