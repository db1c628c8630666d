// Pinch repair: where three labels meet (the ventricle's pool, wall and background), the
// paper's rules, proven for one label, can leave a label's region boundary pinched: a triangle
// in four or more of the region's boundary tetrahedra. The restricted facets around such a
// triangle are sampled at their surface centers (points of ∂Ω on their Voronoi edges, as R5
// uses), which splits them, and the rules run again.
#include <algorithm>
#include <array>
#include <stdexcept>
#include <tuple>

#include "delaunay/facet_key.h"
#include "delaunay/parallel_parts.h"
#include "delaunay/spatial_sort.h"
#include "domain/junctions.h"
#include "refine/refiner.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::VertexKind;

void Refiner::insert_junctions() {
  if (params_.junction_spacing <= 0) return;
  const double spacing = params_.junction_spacing * params_.delta;
  const auto junctions = domain::sample_junctions(
      oracle_, [&](const Point4& p) { return !features_.any_within(p, spacing); },
      [&](const Point4& p) { features_.add(p); });
  std::vector<Point4> points;
  points.reserve(junctions.size());
  for (const auto& j : junctions) points.push_back(j.point);
  // Before any rule runs, straight into the triangulation: the first admit() sees every cell.
  for (std::size_t i : delaunay::spatial_order(points)) tri_.insert(points[i], VertexKind::feature);
}

namespace {

// Scans shorter than this stay on one thread: starting threads would cost more.
constexpr std::size_t kScanPerThread = 4096;

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

unsigned Refiner::scan_parts(std::size_t items) const {
  const std::size_t useful = std::max<std::size_t>(1, items / kScanPerThread);
  return static_cast<unsigned>(std::min<std::size_t>(params_.threads, useful));
}

std::size_t Refiner::count_pinches(std::vector<PinchedTriangle>* pinched, PinchCounts* counts,
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
  const auto& st = tri_.store();
  const unsigned parts = scan_parts(st.cell_slots());
  std::vector<std::vector<std::vector<Record>>> records(parts,
                                                        std::vector<std::vector<Record>>(parts));
  delaunay::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = delaunay::part_range(st.cell_slots(), part, parts);
    for (CellId c = static_cast<CellId>(begin); c < end; ++c) {
      if (!st.is_live(c) || !info_[c].finite) continue;
      const domain::Label own = label_of(c);  // read once: up to 21 uses below
      if (own == 0) continue;
      const auto& cell = st.cell(c);
      for (int i = 0; i < 5; ++i) {
        const CellId n = cell.n[i];
        const domain::Label other = output_label(n);
        if (other == own) continue;
        const delaunay::FacetKey facet = delaunay::facet_key(cell.v, i);
        for (int skip = 0; skip < 4; ++skip) {
          Record r{{own, 0, 0, 0}, 0, c, i};
          for (int k = 0, m = 1; k < 4; ++k)
            if (k != skip) r.key[m++] = facet[k];
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
  delaunay::run_parts(parts, [&](unsigned part) {
    const std::size_t size = table_size(records, part);
    std::vector<Slot> table(size);
    const auto slot_of = [&](const Record& r) -> Slot& {
      for (std::size_t i = r.hash & (size - 1);; i = (i + 1) & (size - 1))
        if (table[i].count == 0 || table[i].key == r.key) return table[i];
    };
    for (const auto& from : records)
      for (const Record& r : from[part]) {
        Slot& slot = slot_of(r);
        slot.key = r.key;
        if (++slot.count == 3) ++pinches[part];
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

void Refiner::link_cycle(CellId start, const std::array<VertexId, 3>& t, std::vector<CellId>& cycle,
                         std::vector<int>& crossed) const {
  // The link of a triangle in a 4D triangulation is a circle: each pentatope around it has two
  // facets through it (opposite its two other vertices), one shared with each neighbor on the
  // cycle. Crossing, each time, the facet opposite the other vertex shared with the previous
  // pentatope walks the cycle.
  const auto& st = tri_.store();
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

void Refiner::pinches_at(CellId start, const std::array<VertexId, 3>& t,
                         std::vector<PinchedTriangle>* pinched) const {
  // A region's boundary facets at t are its label changes along the cycle around t. Asked for
  // every triangle the repair's recount looks at, nearly all unpinched: the cycle and its
  // labels go into reused scratch, and a label's facets are listed only when it has more than
  // two of them.
  const auto& st = tri_.store();
  thread_local std::vector<CellId> cycle;
  thread_local std::vector<int> crossed;  // facet of cycle[i] shared with cycle[i + 1]
  thread_local std::vector<domain::Label> labels, distinct;
  link_cycle(start, t, cycle, crossed);
  const std::size_t n = cycle.size();
  labels.resize(n);
  distinct.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const domain::Label l = labels[i] = output_label(cycle[i]);
    if (l != 0 && std::find(distinct.begin(), distinct.end(), l) == distinct.end())
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

void Refiner::boundary_facets_of(CellId c, int delta, std::vector<DoomedFacet>& out) const {
  const auto& cell = tri_.store().cell(c);
  const domain::Label own = output_label(c);
  for (int i = 0; i < 5; ++i) {
    const domain::Label other = output_label(cell.n[i]);
    if (other == own) continue;
    out.push_back({c, cell.n[i], {delaunay::facet_key(cell.v, i), own, other, delta, c}});
  }
}

void Refiner::note_doomed_facets(Worker& w, int rule) {
  // In a parallel phase this thread holds all these pentatopes and the vertices they share
  // with their neighbors: their labels are stable.
  w.doomed.clear();
  w.doomed_facets.clear();
  w.removed.clear();
  for (CellId c : w.ws->cavity.cells) w.doomed.emplace_back(c, delaunay::kNoVertex);
  if (rule == kR5)
    for (VertexId u : w.near) {
      tri_.incident_cells(u, w.star);
      for (CellId c : w.star) w.doomed.emplace_back(c, u);
    }
  std::sort(w.doomed.begin(), w.doomed.end());
  for (std::size_t i = 0; i < w.doomed.size(); ++i)
    if (i == 0 || w.doomed[i].first != w.doomed[i - 1].first)
      boundary_facets_of(w.doomed[i].first, -1, w.doomed_facets);
}

void Refiner::log_facet_changes(Worker& w) {
  // Dead: the cavity, and the stars of the vertices that were removed (a failed removal leaves
  // its star). A facet between two dead pentatopes went once; one between two new ones came
  // once.
  std::size_t dead = 0;
  for (std::size_t i = 0; i < w.doomed.size(); ++i) {
    const auto [c, u] = w.doomed[i];
    const bool dies = u == delaunay::kNoVertex ||
                      std::find(w.removed.begin(), w.removed.end(), u) != w.removed.end();
    if (dies && (dead == 0 || w.doomed[dead - 1].first != c)) w.doomed[dead++] = w.doomed[i];
  }
  w.doomed.resize(dead);  // sorted by cell, each once
  const auto died = [&](CellId c) {
    const auto it =
        std::lower_bound(w.doomed.begin(), w.doomed.end(), std::pair<CellId, VertexId>{c, 0});
    return it != w.doomed.end() && it->first == c;
  };
  const std::size_t first_change = w.facet_changes.size();
  for (const DoomedFacet& f : w.doomed_facets)
    if (died(f.cell) && !(died(f.other) && f.other < f.cell)) w.facet_changes.push_back(f.change);
  w.doomed_facets.clear();
  for (CellId c : w.fresh) boundary_facets_of(c, +1, w.doomed_facets);
  for (const DoomedFacet& f : w.doomed_facets)
    if (!(f.other < f.cell && std::binary_search(w.fresh.begin(), w.fresh.end(), f.other)))
      w.facet_changes.push_back(f.change);
  w.doomed_facets.clear();
  cancel_opposite_changes(w.facet_changes, first_change);
}

void Refiner::cancel_opposite_changes(std::vector<FacetChange>& changes, std::size_t first) {
  // A facet of the cavity's boundary went with its dead pentatope and came with the new one on
  // the same side: with the same labels, the two changes cancel. Dropped here, before each
  // costs up to eight updates of the pinch counts (37 % of the changes on Pat05 at the files'
  // spacing, 401k → 253k).
  const auto key = [](const FacetChange& f) { return std::tie(f.facet, f.a, f.b, f.delta); };
  std::sort(changes.begin() + static_cast<std::ptrdiff_t>(first), changes.end(),
            [&](const FacetChange& x, const FacetChange& y) { return key(x) < key(y); });
  std::size_t kept = first;
  for (std::size_t i = first; i < changes.size(); ++i) {
    if (i + 1 < changes.size() && changes[i].delta < 0 && changes[i + 1].delta > 0 &&
        changes[i].facet == changes[i + 1].facet && changes[i].a == changes[i + 1].a &&
        changes[i].b == changes[i + 1].b) {
      ++i;  // both go
      continue;
    }
    changes[kept++] = changes[i];
  }
  changes.resize(kept);
}

std::size_t Refiner::count_from_facet_changes(std::vector<PinchedTriangle>* pinched) {
  for (auto& w : workers_) {
    for (const FacetChange& f : w->facet_changes)
      for (const domain::Label l : {f.a, f.b}) {
        if (l == 0) continue;
        for (int skip = 0; skip < 4; ++skip) {
          PinchKey key{l, 0, 0, 0};
          for (int k = 0, m = 1; k < 4; ++k)
            if (k != skip) key[m++] = f.facet[k];
          pinch_counts_.add(key, f.delta, f.cell);
        }
      }
    w->facet_changes.clear();
  }
  // Each pinched triangle walked once, from a pentatope through it: one of its facets in the
  // last count (known_pinches_, sorted by triangle), or the one whose facet pushed a count
  // above two, or else one of its first vertex's star (a star per triangle was 4 % of the run).
  auto keys = pinch_counts_.pinched();
  std::sort(keys.begin(), keys.end(), [](const PinchCounts::Pinch& a, const PinchCounts::Pinch& b) {
    return std::tie(a.key[1], a.key[2], a.key[3], a.key[0]) <
           std::tie(b.key[1], b.key[2], b.key[3], b.key[0]);
  });
  const auto& st = tri_.store();
  std::vector<CellId> star;
  const std::size_t before = pinched->size();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::array<VertexId, 3> t{keys[i].key[1], keys[i].key[2], keys[i].key[3]};
    const auto same_t = [&](std::size_t j) {
      return std::equal(t.begin(), t.end(), keys[j].key.begin() + 1);
    };
    if (i > 0 && same_t(i - 1)) continue;
    const auto through = [&](CellId c) {
      if (!st.is_live(c)) return false;
      int found = 0;
      for (VertexId v : st.cell(c).v) found += v == t[0] || v == t[1] || v == t[2];
      return found == 3;
    };
    CellId start = delaunay::kNoCell;
    auto known = std::lower_bound(
        known_pinches_.begin(), known_pinches_.end(), t,
        [](const PinchedTriangle& p, const std::array<VertexId, 3>& x) { return p.triangle < x; });
    for (; known != known_pinches_.end() && known->triangle == t && start == delaunay::kNoCell;
         ++known)
      for (const auto& [c, facet] : known->facets)
        if (through(c)) {
          start = c;
          break;
        }
    for (std::size_t j = i; j < keys.size() && same_t(j) && start == delaunay::kNoCell; ++j)
      if (through(keys[j].cell)) start = keys[j].cell;
    if (start == delaunay::kNoCell) {
      tri_.incident_cells(t[0], star);
      for (CellId c : star)
        if (through(c)) {
          start = c;
          break;
        }
    }
    if (start != delaunay::kNoCell) pinches_at(start, t, pinched);
  }
  return pinched->size() - before;
}

std::size_t Refiner::count_for_repair() {
  pinches_current_ = false;
  std::vector<PinchedTriangle> pinched;
  // The first count scans everything; later ones follow the facet changes.
  const std::size_t found = counting_facets_ ? count_from_facet_changes(&pinched)
                                             : count_pinches(&pinched, &pinch_counts_, true);
  if (check_counts_ && counting_facets_) {
    std::vector<PinchedTriangle> full;
    PinchCounts counts;
    count_pinches(&full, &counts);
    if (!(counts == pinch_counts_))
      throw std::logic_error(
          "Refiner: the triangles' counts from facet changes differ from a full count");
    sort_canonically(full);
    sort_canonically(pinched);
    const auto same = [](const PinchedTriangle& a, const PinchedTriangle& b) {
      return a.triangle == b.triangle && a.facets == b.facets;
    };
    if (!std::equal(pinched.begin(), pinched.end(), full.begin(), full.end(), same))
      throw std::logic_error(
          "Refiner: the pinches counted from facet changes differ from a full count");
  }
  counting_facets_ = true;
  // In canonical order: the repair's points go in in this order, however the list was found.
  sort_canonically(pinched);
  known_pinches_ = std::move(pinched);
  return found;
}

bool Refiner::repair_point_of(const PinchedTriangle& t, Point4* point, CellId* hint) const {
  // The surface center of its largest restricted facet (the one the rules left coarsest).
  const auto& st = tri_.store();
  double largest = -1;
  for (const auto& [c, i] : t.facets) {
    const CellId n = st.cell(c).n[i];
    if (!info_[n].finite) continue;
    const auto z = oracle_.first_crossing(info_[c].center, info_[n].center);
    if (!z) continue;
    const Point4& v = st.point(st.cell(c).v[(i + 1) % 5]);
    double r2 = 0;
    for (int k = 0; k < 4; ++k) r2 += (z->point[k] - v[k]) * (z->point[k] - v[k]);
    if (r2 > largest) largest = r2, *point = z->point, *hint = c;
  }
  return largest >= 0;
}

std::size_t Refiner::repair_pinches(double min_spacing) {
  // A point per pinched triangle; all are found before any goes in, as cells die with
  // insertions.
  std::vector<RepairPoint> points;
  const auto& st = tri_.store();
  decltype(refused_) refused;  // this round's
  for (const PinchedTriangle& t : known_pinches_) {
    Point4 point;
    CellId hint = delaunay::kNoCell;
    if (const auto it = refused_.find(t.facets);
        it != refused_.end() && still_refused(t, it->second, min_spacing)) {
      if (check_refused_) {
        ++refused_rechecked_;
        if (!repair_point_of(t, &point, &hint) || point != it->second.point ||
            !feature_within(point, min_spacing))
          throw std::logic_error("Refiner: a refused repair point would not be refused again");
      }
      refused.insert(refused_.extract(it));
      continue;
    }
    if (!repair_point_of(t, &point, &hint)) continue;
    // A point near a sampled one is refused (insert_repair_points() asks again, as points of
    // this round go in first).
    if (feature_within(point, min_spacing)) {
      RefusedPoint& record = refused[t.facets];
      record.point = point;
      record.spacing = min_spacing;
      for (const auto& [c, i] : t.facets) {
        const CellId n = st.cell(c).n[i];
        record.neighbors.push_back(n);
        record.vertices.insert(record.vertices.end(), std::begin(st.cell(c).v),
                               std::end(st.cell(c).v));
        record.vertices.insert(record.vertices.end(), std::begin(st.cell(n).v),
                               std::end(st.cell(n).v));
      }
      continue;
    }
    RepairPoint r{point, {hint, {}}};
    std::copy(std::begin(st.cell(hint).v), std::end(st.cell(hint).v), r.hint.v);
    points.push_back(r);
  }
  refused_ = std::move(refused);
  return insert_repair_points(points, min_spacing);
}

bool Refiner::still_refused(const PinchedTriangle& t, const RefusedPoint& refused,
                            double spacing) const {
  if (refused.spacing != spacing) return false;
  const auto& st = tri_.store();
  for (std::size_t k = 0; k < t.facets.size(); ++k) {
    const auto [c, i] = t.facets[k];
    const CellId n = refused.neighbors[k];
    if (!st.still_holds(c, &refused.vertices[10 * k]) || st.cell(c).n[i] != n ||
        !st.still_holds(n, &refused.vertices[10 * k + 5]))
      return false;
  }
  return true;
}

}  // namespace mesh4d::refine
