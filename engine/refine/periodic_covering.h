// The 3-sheeted covering of periodic time (domain/periodic_time.h) as the refiner sees it: which
// pentatopes are their class's representative (the middle sheet's), where points may be
// inserted, each point's copies one period below and above, and each vertex's and pentatope's
// twins in the other sheets.
//
// The rules run on representatives only, and every insertion puts in all three copies, so the
// point set stays invariant under a shift by T within the covering. Labels a stage sets by hand
// (relabeling) go to every twin. Near the covering's outer ends, where the tiled image is cut
// off, nothing is trusted: no point is inserted for what happens there.
#pragma once

#include <array>
#include <unordered_map>
#include <vector>

#include "delaunay/triangulation.h"
#include "domain/periodic_time.h"

namespace mesh4d::refine {

class PeriodicCovering {
 public:
  PeriodicCovering() = default;
  /// `margin`: how far the covering reaches past each end of the period (0: a whole period);
  /// `trusted`: how far its trusted band does (0: half the margin).
  PeriodicCovering(const domain::TimePeriod& period, double margin, double trusted = 0)
      : period_(period),
        margin_(margin > 0 ? margin : period.length),
        trusted_(trusted > 0 ? trusted : margin_ / 2) {}

  bool active() const { return period_.periodic(); }
  const domain::TimePeriod& period() const { return period_; }

  /// Whether t lies in the middle sheet [start, start + T).
  bool in_middle(double t) const {
    return t >= period_.start && t < period_.start + period_.length;
  }
  /// Whether something at time t is counted: in the middle sheet, or anywhere in open time.
  bool counts(double t) const { return !active() || in_middle(t); }
  /// Whether a point lies in the trusted band, where the covering's image is the cycle's and
  /// its cut-off ends' surface is not near: within `trusted` of the middle sheet (always, when
  /// time is open). Only such points go in.
  bool trusted(const Point4& p) const {
    return !active() ||
           (p[3] >= period_.start - trusted_ && p[3] < period_.start + period_.length + trusted_);
  }
  /// How far the trusted band reaches past each end of the period.
  double trusted_reach() const { return trusted_; }
  /// Whether a point lies in the covering (within the margin of the middle sheet): a copy
  /// beyond it is not inserted.
  bool in_covering(const Point4& p) const {
    return p[3] >= period_.start - margin_ && p[3] < period_.start + period_.length + margin_;
  }
  /// The lowest t of a pentatope's vertices (its anchor: a class's representative is the copy
  /// anchored in the middle sheet).
  static double anchor(const delaunay::Triangulation& tri, delaunay::CellId c);
  /// Whether c represents its class (always, when time is open).
  bool representative(const delaunay::Triangulation& tri, delaunay::CellId c) const {
    return !active() || in_middle(anchor(tri, c));
  }

  /// Whether the rules look at c: a representative, or a pentatope with a box corner (such
  /// pentatopes have no translates; at the start all of them have one).
  bool rules_apply(const delaunay::Triangulation& tri, delaunay::CellId c) const;
  /// p's copies: p wrapped into the middle sheet, then one period below and one above (those
  /// two may lie beyond the covering: in_covering).
  std::array<Point4, 3> copies(const Point4& p) const;
  /// Records vertex v at point p, for the twin lookups.
  void add(mesh4d::VertexId v, const Point4& p) { where_[p] = v; }
  /// The live vertex at exactly p, or kNoVertex.
  mesh4d::VertexId vertex_at(const delaunay::Triangulation& tri, const Point4& p) const;
  /// The vertex that was inserted at exactly p, live or not, or kNoVertex (reads no vertex: for
  /// a thread that must lock the vertex before it looks at it).
  mesh4d::VertexId vertex_inserted_at(const Point4& p) const;
  /// The vertex at v's point shifted by `periods` · T, or kNoVertex.
  mesh4d::VertexId twin(const delaunay::Triangulation& tri, mesh4d::VertexId v, int periods) const;
  /// The pentatopes that are c's translates in the other sheets of the covering (those that
  /// exist: a pentatope larger than the covering's margins may have none), for a trusted c.
  void twin_cells(const delaunay::Triangulation& tri, delaunay::CellId c,
                  std::vector<delaunay::CellId>& out) const;

 private:
  struct PointHash {
    std::size_t operator()(const Point4& p) const;
  };
  domain::TimePeriod period_;
  double margin_ = 0;
  double trusted_ = 0;
  std::unordered_map<Point4, mesh4d::VertexId, PointHash> where_;
};

}  // namespace mesh4d::refine
