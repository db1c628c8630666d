// Pinch repair: where three labels meet (the ventricle's pool, wall and background), the
// paper's rules, proven for one label, can leave a label's region boundary pinched: a triangle
// in four or more of the region's boundary tetrahedra. The restricted facets around such a
// triangle are sampled at their surface centers (points of ∂Ω on their Voronoi edges, as R5
// uses), which splits them, and the rules run again.
#include <algorithm>
#include <array>

#include "delaunay/spatial_sort.h"
#include "domain/junctions.h"
#include "refine/parallel_parts.h"
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

std::uint64_t hash_key(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  std::uint64_t h = (std::uint64_t(a) << 32 | b) * 0x9E3779B97F4A7C15ull;
  h ^= (std::uint64_t(c) << 32 | d) * 0xC2B2AE3D27D4EB4Full;
  return h ^ (h >> 29);
}

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

std::size_t Refiner::count_pinches(std::vector<PinchedTriangle>* pinched) const {
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
  run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = part_range(st.cell_slots(), part, parts);
    for (CellId c = static_cast<CellId>(begin); c < end; ++c) {
      if (!st.is_live(c) || st.is_infinite(c) || !info_[c].finite || info_[c].label == 0) continue;
      const auto& cell = st.cell(c);
      for (int i = 0; i < 5; ++i) {
        const CellId n = cell.n[i];
        const domain::Label other = st.is_infinite(n) || !info_[n].finite ? 0 : info_[n].label;
        if (other == info_[c].label) continue;
        std::array<std::uint32_t, 4> facet;
        for (int k = 0, m = 0; k < 5; ++k)
          if (k != i) facet[m++] = cell.v[k];
        std::sort(facet.begin(), facet.end());
        for (int skip = 0; skip < 4; ++skip) {
          Record r{{info_[c].label, 0, 0, 0}, 0, c, i};
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
  std::vector<std::size_t> pinches(parts, 0);
  std::vector<std::vector<PinchedTriangle>> found(parts);
  run_parts(parts, [&](unsigned part) {
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
    if (!pinched || pinches[part] == 0) return;
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
  });
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

std::size_t Refiner::recount_pinches(std::vector<PinchedTriangle>* pinched) {
  // Candidate triangles with a live pentatope through each, handed (as in count_pinches) to
  // the part their triangle hashes to.
  using Triangle = std::array<VertexId, 3>;
  using Through = std::pair<Triangle, CellId>;
  const auto& st = tri_.store();
  // Slots are reused as the rules churn: each once (a fifth of the list on the ventricle).
  std::vector<std::uint64_t> listed((st.cell_slots() + 63) / 64, 0);
  std::size_t unique = 0;
  for (const CellId c : touched_) {
    std::uint64_t& word = listed[c / 64];
    const std::uint64_t bit = std::uint64_t(1) << (c % 64);
    if (!(word & bit)) word |= bit, touched_[unique++] = c;
  }
  touched_.resize(unique);
  const unsigned parts = scan_parts(touched_.size());
  const auto part_of = [parts](const Triangle& t) {
    return bucket_of(hash_key(t[0], t[1], t[2], 0), parts);
  };
  std::vector<std::vector<std::vector<Through>>> candidates(
      parts, std::vector<std::vector<Through>>(parts));
  run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = part_range(touched_.size(), part, parts);
    for (std::size_t j = begin; j < end; ++j) {
      const CellId c = touched_[j];
      if (!st.is_live(c) || st.is_infinite(c)) continue;
      const auto& cell = st.cell(c);
      const domain::Label own = info_[c].finite ? info_[c].label : 0;
      for (int i = 0; i < 5; ++i) {
        const CellId nb = cell.n[i];
        const domain::Label other = st.is_infinite(nb) || !info_[nb].finite ? 0 : info_[nb].label;
        if (other == own) continue;
        std::array<VertexId, 4> facet;
        for (int k = 0, m = 0; k < 5; ++k)
          if (k != i) facet[m++] = cell.v[k];
        std::sort(facet.begin(), facet.end());
        for (int skip = 0; skip < 4; ++skip) {
          Triangle t;
          for (int k = 0, m = 0; k < 4; ++k)
            if (k != skip) t[m++] = facet[k];
          candidates[part][part_of(t)].emplace_back(t, c);
        }
      }
    }
  });
  std::vector<CellId> star;
  for (const PinchedTriangle& p : known_pinches_) {
    // A pentatope of the old pinch may be gone; any live one through the triangle will do.
    CellId through = delaunay::kNoCell;
    for (const auto& [c, i] : p.facets)
      if (st.is_live(c) && !st.is_infinite(c)) {
        int found = 0;
        for (VertexId v : st.cell(c).v)
          found += v == p.triangle[0] || v == p.triangle[1] || v == p.triangle[2];
        if (found == 3) {
          through = c;
          break;
        }
      }
    bool alive = true;
    for (VertexId v : p.triangle) alive = alive && st.vertex(v).kind != VertexKind::removed;
    if (through == delaunay::kNoCell && alive) {
      tri_.incident_cells(p.triangle[0], star);
      for (CellId c : star) {
        int found = 0;
        for (VertexId v : st.cell(c).v) found += v == p.triangle[1] || v == p.triangle[2];
        if (found == 2) {
          through = c;
          break;
        }
      }
    }
    if (through != delaunay::kNoCell)
      candidates[0][part_of(p.triangle)].emplace_back(p.triangle, through);
  }
  std::vector<std::vector<PinchedTriangle>> found(parts);
  run_parts(parts, [&](unsigned part) {
    // Each triangle once (a hash set: sorting the candidates cost more than the walks).
    const std::size_t size = table_size(candidates, part);
    std::vector<Through> seen(size, Through{{}, delaunay::kNoCell});
    for (const auto& from : candidates)
      for (const auto& [t, c] : from[part]) {
        const std::uint64_t h = hash_key(t[0], t[1], t[2], 0);
        for (std::size_t i = h & (size - 1);; i = (i + 1) & (size - 1)) {
          if (seen[i].second == delaunay::kNoCell) {
            seen[i] = {t, c};
            pinches_at(c, t, &found[part]);
            break;
          }
          if (seen[i].first == t) break;
        }
      }
  });
  // In triangle order (and for each triangle, in the order pinches_at lists its labels): the
  // repair's order depends neither on the hashing nor on the number of parts.
  const std::size_t before = pinched->size();
  for (auto& part : found)
    pinched->insert(pinched->end(), std::make_move_iterator(part.begin()),
                    std::make_move_iterator(part.end()));
  std::stable_sort(
      pinched->begin() + static_cast<std::ptrdiff_t>(before), pinched->end(),
      [](const PinchedTriangle& a, const PinchedTriangle& b) { return a.triangle < b.triangle; });
  return pinched->size() - before;
}

std::size_t Refiner::count_for_repair() {
  pinches_current_ = false;
  std::vector<PinchedTriangle> pinched;
  // The first count scans everything; later ones look only where pentatopes changed.
  const std::size_t found = tracking_ ? recount_pinches(&pinched) : count_pinches(&pinched);
  tracking_ = true;
  touched_.clear();
  known_pinches_ = std::move(pinched);
  return found;
}

std::size_t Refiner::repair_pinches(double min_spacing) {
  const std::vector<PinchedTriangle>& pinched = known_pinches_;
  // Per pinched triangle, the surface center of its largest restricted facet (the one the
  // rules left coarsest); all are found before any goes in, as cells die with insertions.
  std::vector<RepairPoint> points;
  const auto& st = tri_.store();
  for (const PinchedTriangle& t : pinched) {
    double largest = -1;
    Point4 best;
    CellId hint = delaunay::kNoCell;
    for (const auto& [c, i] : t.facets) {
      const CellId n = st.cell(c).n[i];
      if (st.is_infinite(n) || !info_[n].finite) continue;
      const auto z = oracle_.first_crossing(info_[c].center, info_[n].center);
      if (!z) continue;
      const Point4& v = st.point(st.cell(c).v[(i + 1) % 5]);
      double r2 = 0;
      for (int k = 0; k < 4; ++k) r2 += (z->point[k] - v[k]) * (z->point[k] - v[k]);
      if (r2 > largest) largest = r2, best = z->point, hint = c;
    }
    if (largest >= 0) {
      RepairPoint r{best, {hint, {}}};
      std::copy(std::begin(st.cell(hint).v), std::end(st.cell(hint).v), r.hint.v);
      points.push_back(r);
    }
  }
  return insert_repair_points(points, min_spacing);
}

}  // namespace mesh4d::refine
