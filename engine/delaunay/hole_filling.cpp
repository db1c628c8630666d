#include "delaunay/hole_filling.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "delaunay/facet_key.h"
#include "delaunay/geometry.h"
#include "delaunay/predicates.h"

namespace mesh4d::delaunay {
namespace {

bool same_key(const FacetKey& a, const FacetKey& b) {
  return ((a[0] ^ b[0]) | (a[1] ^ b[1]) | (a[2] ^ b[2]) | (a[3] ^ b[3])) == 0;
}

// Facets by their sorted vertex ids, each with the one pentatope seen on it so far (a fill index,
// or ~hole facet) until a second one closes it. Open addressing; a hole has a few hundred facets.
class FacetTable {
 public:
  struct Entry {
    FacetKey key;
    std::int32_t owner;  // fill index, or ~hole facet index
    std::int8_t slot;    // the facet's index in the owner (fill pentatopes only)
    bool open;
  };

  // Empty, sized for about `facets` entries (it grows past them).
  void reset(std::size_t facets) {
    std::size_t size = 64;
    while (size < 2 * facets) size *= 2;
    entries_.assign(size, Entry{{kNoVertex, 0, 0, 0}, 0, 0, false});
    mask_ = size - 1;
    count_ = open_ = 0;
  }
  // The entry of `key`, or nullptr after adding it (then open() records its first pentatope).
  Entry* find(const FacetKey& key) {
    if (2 * (count_ + 1) > entries_.size()) grow();
    std::size_t h = (key[0] * 0x9E3779B1u) ^ (key[1] * 0x85EBCA77u) ^ (key[2] * 0xC2B2AE3Du) ^
                    (key[3] * 0x27D4EB2Fu);
    for (std::size_t i = (h ^ (h >> 15)) & mask_;; i = (i + 1) & mask_) {
      Entry& e = entries_[i];
      if (same_key(e.key, key)) return &e;
      if (e.key[0] == kNoVertex) {
        e = {key, 0, 0, false};
        ++count_;
        last_ = &e;
        return nullptr;
      }
    }
  }
  // Records the first pentatope on the facet find() just added.
  void open(std::int32_t owner, int slot) {
    *last_ = {last_->key, owner, static_cast<std::int8_t>(slot), true};
    ++open_;
  }
  // Joins fill pentatope x (facet j) to the one recorded on e; false when e is already closed
  // (a third pentatope on the facet).
  bool join(Entry& e, std::vector<FillCell>& fill, std::int32_t x, int j) {
    if (!e.open) return false;
    fill[x].n[j] = e.owner;
    if (e.owner >= 0) fill[e.owner].n[e.slot] = x;
    e.open = false;
    --open_;
    return true;
  }
  bool any_open() const { return open_ > 0; }

 private:
  void grow() {
    std::vector<Entry> old;
    old.swap(entries_);
    const std::size_t open = open_;
    reset(old.size());
    for (const Entry& e : old)
      if (e.key[0] != kNoVertex) {
        find(e.key);
        *last_ = e;
      }
    open_ = open;
  }
  std::vector<Entry> entries_;
  Entry* last_ = nullptr;
  std::size_t mask_ = 0, count_ = 0, open_ = 0;
};

// The facet opposite `slot` of a positively oriented vertex array `a` and the link vertices
// that could complete it on the side where a[slot] would be: the pencil of spheres through the
// facet, ranked in floating point by how far their center lies towards that side.
class ApexSearch {
 public:
  ApexSearch(const PentatopeStore& store, const VertexId a[5], int slot) {
    for (int i = 0, k = 0; i < 5; ++i)
      if (i != slot) f_[k++] = &store.point(a[i]);
    // orient4(a with u at slot) = ±det[f1-f0; f2-f0; f3-f0; u-f0] (moving the slot last is a
    // cyclic shift over 4 - slot places) = normal_ · (u - f0).
    const Tetrahedron4 facet{*f_[0], *f_[1], *f_[2], *f_[3]};
    const double sign = (4 - slot) % 2 == 0 ? 1 : -1;
    const Point4 n = hyperplane_normal(facet);
    for (int k = 0; k < 4; ++k) normal_[k] = sign * n[k];
    center_ = facet_circumcenter(facet);
    radius2_ = squared_distance(center_, *f_[0]);
    scale_ = std::sqrt(std::max({squared_distance(*f_[1], *f_[0]), squared_distance(*f_[2], *f_[0]),
                                 squared_distance(*f_[3], *f_[0])}));
    normal_norm_ = std::sqrt(dot(normal_, normal_));
    ok_ = std::isfinite(radius2_) && normal_norm_ > 0;
  }

  bool ok() const { return ok_; }
  // Heights below this may have the wrong sign (see measure()).
  double uncertain_height() const { return 1e-9 * scale_ * normal_norm_; }
  // For n points u given by coordinate arrays: height, the distance of u from the facet's
  // hyperplane times |normal|, positive on the open side (orient4's sign where it is not too
  // small to trust); and power, |u − c|² − r² for the facet's circumsphere (c, r). The spheres
  // through the facet and a point on the open side rank by twice how far their center lies
  // towards that side, power |normal| / height: the sphere of smallest rank holds no other point
  // there. Candidates compare by cross-multiplying (no division per link vertex), and the pass
  // has no branch (the compiler vectorizes it): the wrap asks it of every link vertex for every
  // facet it opens.
  void measure(const double* const xyzt[4], std::size_t n, double* __restrict height,
               double* __restrict power) const {
    const double* __restrict x = xyzt[0];
    const double* __restrict y = xyzt[1];
    const double* __restrict z = xyzt[2];
    const double* __restrict t = xyzt[3];
    const Point4& f = *f_[0];
    const double n0 = normal_[0], n1 = normal_[1], n2 = normal_[2], n3 = normal_[3];
    const double c0 = center_[0], c1 = center_[1], c2 = center_[2], c3 = center_[3];
    const double f0 = f[0], f1 = f[1], f2 = f[2], f3 = f[3], r2 = radius2_;
    for (std::size_t i = 0; i < n; ++i) {
      height[i] = n0 * (x[i] - f0) + n1 * (y[i] - f1) + n2 * (z[i] - f2) + n3 * (t[i] - f3);
      const double d0 = x[i] - c0, d1 = y[i] - c1, d2 = z[i] - c2, d3 = t[i] - c3;
      power[i] = d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3 - r2;
    }
  }

  double rank(double power, double h) const { return power * normal_norm_ / h; }
  bool ranks_within(double power, double h, double limit) const {
    return power * normal_norm_ <= limit * h;
  }
  // Ranks closer than this to each other are compared exactly.
  double rank_margin(double rank) const { return 1e-7 * (std::abs(rank) + scale_); }

 private:
  static double dot(const double a[4], const double b[4]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  }
  const Point4* f_[4];
  double normal_[4];
  Point4 center_;
  double radius2_ = 0, scale_ = 0, normal_norm_ = 0;
  bool ok_ = false;
};

// The link vertex that completes the facet opposite `slot` of `a` into a Delaunay pentatope on
// that side; kNoVertex when none is found. `xyzt` are the link vertices' coordinates, gathered
// once per hole (each is read for every facet the wrap opens).
VertexId find_apex(const PentatopeStore& store, VertexId a[5], int slot,
                   const std::vector<VertexId>& link, const double* const xyzt[4],
                   std::vector<VertexId>& close) {
  const ApexSearch search(store, a, slot);
  if (!search.ok()) return kNoVertex;
  const double uncertain = search.uncertain_height();
  struct Ranked {
    VertexId u;
    double power, height;
  };
  thread_local std::vector<Ranked> ranked;
  thread_local std::vector<double> heights, powers;
  ranked.clear();
  close.clear();
  heights.resize(link.size());
  powers.resize(link.size());
  search.measure(xyzt, link.size(), heights.data(), powers.data());
  // The best so far as a fraction power / height (heights are positive here).
  VertexId best = kNoVertex;
  double best_power = 0, best_height = 0;
  for (std::size_t i = 0; i < link.size(); ++i) {
    const VertexId u = link[i];
    if (u == a[0] || u == a[1] || u == a[2] || u == a[3] || u == a[4]) continue;
    const double h = heights[i];
    if (h <= uncertain) {
      if (h > -uncertain) close.push_back(u);  // its side is decided exactly below
      continue;
    }
    const double power = powers[i];
    ranked.push_back({u, power, h});
    if (best == kNoVertex || power * best_height < best_power * h)
      best = u, best_power = power, best_height = h;
  }
  // Candidates ranked within rounding of the best are compared exactly (with the tie-break).
  if (best != kNoVertex) {
    const double best_rank = search.rank(best_power, best_height);
    const double limit = best_rank + search.rank_margin(best_rank);
    for (const Ranked& r : ranked)
      if (r.u != best && search.ranks_within(r.power, r.height, limit)) close.push_back(r.u);
  }
  const VertexId keep = a[slot];
  for (VertexId u : close) {
    a[slot] = u;
    const Point4* s[5];
    for (int i = 0; i < 5; ++i) s[i] = &store.point(a[i]);
    if (orient4(*s[0], *s[1], *s[2], *s[3], *s[4]) <= 0) continue;
    if (best == kNoVertex) {
      best = u;
      continue;
    }
    a[slot] = best;
    const Point4* t[5];
    for (int i = 0; i < 5; ++i) t[i] = &store.point(a[i]);
    if (insphere4_sos(t, a, store.point(u), u) > 0) best = u;
  }
  a[slot] = keep;
  return best;
}

// The proof that `fill` is the Delaunay filling: positive orientations, and across every facet
// the pentatope beyond keeps its far vertex outside the sphere of the one on this side.
bool locally_delaunay(const PentatopeStore& store, const std::vector<HoleFacet>& hole,
                      const std::vector<FillCell>& fill) {
  for (std::size_t x = 0; x < fill.size(); ++x) {
    const FillCell& c = fill[x];
    const Point4* s[5];
    for (int i = 0; i < 5; ++i) s[i] = &store.point(c.v[i]);
    if (orient4(*s[0], *s[1], *s[2], *s[3], *s[4]) <= 0) return false;
    for (int i = 0; i < 5; ++i) {
      VertexId far = kNoVertex;
      if (c.n[i] >= 0) {
        if (static_cast<std::size_t>(c.n[i]) < x) continue;  // checked from the other side
        const FillCell& d = fill[c.n[i]];
        for (VertexId u : d.v)
          if (std::find(c.v, c.v + 5, u) == c.v + 5) far = u;
      } else {
        const HoleFacet& h = hole[~c.n[i]];
        if (store.is_infinite(h.outside)) continue;
        far = store.cell(h.outside).v[h.outside_slot];
      }
      if (far == kNoVertex || insphere4_sos(s, c.v, store.point(far), far) >= 0) return false;
    }
  }
  return true;
}

}  // namespace

HoleCounters& hole_counters() {
  thread_local HoleCounters counters;
  return counters;
}

bool wrap_hole(const PentatopeStore& store, const std::vector<HoleFacet>& hole,
               const std::vector<VertexId>& link, std::vector<FillCell>& fill) {
  // Work: facets with one pentatope, as the vertex array of the pentatope that would have
  // the apex at `slot` on the open side, positively oriented.
  struct Open {
    VertexId a[5];
    int slot;
  };
  thread_local FacetTable table;
  thread_local std::vector<Open> work;
  thread_local std::vector<VertexId> close;
  thread_local std::vector<double> coordinates[4];
  for (int k = 0; k < 4; ++k) {
    coordinates[k].resize(link.size());
    for (std::size_t i = 0; i < link.size(); ++i) coordinates[k][i] = store.point(link[i])[k];
  }
  const double* const xyzt[4] = {coordinates[0].data(), coordinates[1].data(),
                                 coordinates[2].data(), coordinates[3].data()};
  fill.clear();
  work.clear();
  table.reset(3 * hole.size());
  for (std::size_t b = 0; b < hole.size(); ++b) {
    Open o;
    const Pentatope& c = store.cell(hole[b].star_cell);
    std::copy(c.v, c.v + 5, o.a);
    o.slot = hole[b].slot;
    if (table.find(facet_key(o.a, o.slot))) return false;
    table.open(~static_cast<std::int32_t>(b), 0);
    work.push_back(o);
  }
  const std::size_t limit = 8 * hole.size() + 64;  // a fill is smaller than its boundary
  while (!work.empty()) {
    Open o = work.back();
    work.pop_back();
    FacetTable::Entry* e = table.find(facet_key(o.a, o.slot));
    if (!e) return false;
    if (!e->open) continue;
    const VertexId apex = find_apex(store, o.a, o.slot, link, xyzt, close);
    if (apex == kNoVertex || fill.size() >= limit) return false;
    const auto x = static_cast<std::int32_t>(fill.size());
    FillCell cell;
    std::copy(o.a, o.a + 5, cell.v);
    cell.v[o.slot] = apex;
    std::fill(cell.n, cell.n + 5, 0);
    fill.push_back(cell);
    table.join(*e, fill, x, o.slot);
    for (int j = 0; j < 5; ++j) {
      if (j == o.slot) continue;
      if (FacetTable::Entry* f = table.find(facet_key(fill[x].v, j))) {
        if (!table.join(*f, fill, x, j)) return false;
        continue;
      }
      table.open(x, j);
      // The other side: the same facet with two of its vertices swapped is positively
      // oriented with an apex beyond it.
      Open next;
      std::copy(fill[x].v, fill[x].v + 5, next.a);
      const int p = j == 0 ? 1 : 0, q = j <= 1 ? 2 : 1;
      std::swap(next.a[p], next.a[q]);
      next.slot = j;
      work.push_back(next);
    }
  }
  if (table.any_open() || !locally_delaunay(store, hole, fill)) return false;
  return true;
}

bool link_fill(const PentatopeStore& store, const std::vector<HoleFacet>& hole,
               std::vector<FillCell>& fill) {
  thread_local FacetTable table;
  table.reset(hole.size() + 5 * fill.size());
  for (std::size_t b = 0; b < hole.size(); ++b) {
    const Pentatope& c = store.cell(hole[b].star_cell);
    if (table.find(facet_key(c.v, hole[b].slot))) return false;
    table.open(~static_cast<std::int32_t>(b), 0);
  }
  for (std::size_t x = 0; x < fill.size(); ++x)
    for (int j = 0; j < 5; ++j) {
      FacetTable::Entry* e = table.find(facet_key(fill[x].v, j));
      if (!e) {
        table.open(static_cast<std::int32_t>(x), j);
      } else if (!table.join(*e, fill, static_cast<std::int32_t>(x), j)) {
        return false;
      }
    }
  return !table.any_open();
}

}  // namespace mesh4d::delaunay
