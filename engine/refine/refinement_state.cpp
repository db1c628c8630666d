#include "refine/refinement_state.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "delaunay/circumballs.h"
#include "delaunay/exact_circumcenter.h"
#include "delaunay/spatial_sort.h"
#include "domain/junctions.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::VertexKind;

RefinementState::RefinementState(const domain::SurfaceOracle& oracle_in,
                                 const RefineParams& params_in)
    : oracle(oracle_in),
      params(params_in),
      covering(domain::TimePeriod{params_in.period_start, params_in.period},
               params_in.period_margin, params_in.period_trusted),
      features(params_in.delta) {}

void RefinementState::set_twin_labels(CellId c, domain::Label label) {
  // Outside the trusted band a pentatope's twins are not its translates' labels to set.
  if (!covering.trusted({0, 0, 0, PeriodicCovering::anchor(tri, c)})) return;
  std::vector<CellId> twins;
  covering.twin_cells(tri, c, twins);
  for (CellId t : twins) info[t].label_code = std::uint32_t{label} + 1;
}

void RefinementState::insert_box() {
  // The bounding box of the foreground voxels, grown so that its corners are at least 2Δ from
  // ∂Ω (which lies within a voxel-cell diagonal of foreground voxel centers).
  const domain::LabelImage4& image = oracle.image();
  const auto& d = image.dims();
  std::array<std::size_t, 4> lo{d[0], d[1], d[2], d[3]}, hi{0, 0, 0, 0};
  for (std::size_t t = 0, i = 0; t < d[3]; ++t)
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x, ++i) {
          if (image.at(i) == 0) continue;
          const std::size_t c[4] = {x, y, z, t};
          for (int a = 0; a < 4; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
        }
  double diagonal = 0;
  for (double s : image.spacing()) diagonal += s * s;
  const double margin = 2 * params.delta + std::sqrt(diagonal);
  const Point4 a = image.voxel_center(lo[0], lo[1], lo[2], lo[3]);
  const Point4 b = image.voxel_center(hi[0], hi[1], hi[2], hi[3]);
  for (int k = 0; k < 4; ++k) box[0][k] = a[k] - margin, box[1][k] = b[k] + margin;
  for (int corner = 0; corner < 16; ++corner) {
    Point4 p;
    for (int k = 0; k < 4; ++k) p[k] = box[(corner >> k) & 1][k];
    tri.insert(p, VertexKind::box);
  }
}

void RefinementState::insert_junctions() {
  if (params.junction_spacing <= 0) return;
  const double spacing = params.junction_spacing * params.delta;
  const auto junctions = domain::sample_junctions(
      oracle, [&](const Point4& p) { return !features.any_within(p, spacing); },
      [&](const Point4& p) { features.add(p); });
  std::vector<Point4> points;
  points.reserve(junctions.size());
  for (const auto& j : junctions)  // in periodic time each once, from the middle sheet's copy
    if (covering.counts(j.point[3])) points.push_back(j.point);
  // Before any rule runs, straight into the triangulation: the first admit() sees every cell.
  // A point's copies go in one after the other, with consecutive ids, as the rules' do.
  for (std::size_t i : delaunay::spatial_order(points)) {
    if (!covering.active()) {
      tri.insert(points[i], VertexKind::feature);
      continue;
    }
    for (const Point4& p : covering.copies(points[i]))
      if (covering.in_covering(p)) covering.add(tri.insert(p, VertexKind::feature).vertex, p);
  }
}

namespace {

// Periodic time: a pentatope's vertices in the order of their ids. A point's copies are
// inserted together, with consecutive ids, so any two vertices are in the same order as their
// translates (periodic_covering.h), and every translate of a pentatope measures its circumball
// from its points in the same order (translate_invariant_label). A sorting network of min and
// max: admit() sorts every new pentatope's ids.
void sort_ids(VertexId v[5]) {
  static constexpr int kNetwork[9][2] = {{0, 1}, {3, 4}, {2, 4}, {2, 3}, {1, 4},
                                         {0, 3}, {0, 2}, {1, 3}, {1, 2}};
  for (const auto& [i, j] : kNetwork) {
    const VertexId lo = std::min(v[i], v[j]);
    v[j] = std::max(v[i], v[j]);
    v[i] = lo;
  }
}

// A pentatope whose double center has no error bound: its ball from exact determinants. Where
// the double determinant rounds to zero, though the exact orientation is positive, the
// pentatope would otherwise take no rule and no label, and stand as a hole of the background
// inside a region, with its free vertices on the region's boundary; where it does not, the
// rounded center can lie a good part of the radius off, in another label. Its ball decides no
// in-sphere question alone (center_error infinite).
bool exact_ball(const Point4* const vertices[5], CellInfo& i) {
  const std::optional<Point4> center = delaunay::exact_circumcenter(vertices);
  if (!center) return false;
  i.center = *center;
  i.radius = 0;
  for (int k = 0; k < 5; ++k) i.radius += distance(*center, *vertices[k]) / 5;
  i.center_error = std::numeric_limits<float>::infinity();
  return std::isfinite(i.radius);
}

}  // namespace

void RefinementState::admit(const std::vector<CellId>& cells) {
  // The finite pentatopes' circumballs four at a time (circumballs4: the same numbers as one
  // at a time, faster); a short last group is padded with its first pentatope.
  const auto& st = tri.store();
  CellId group[4];
  const Point4* vertices[4][5];
  int n = 0;
  const auto measure = [&] {
    for (int l = n; l < 4; ++l) std::copy(vertices[0], vertices[0] + 5, vertices[l]);
    delaunay::Circumball balls[4];
    delaunay::circumballs4(vertices, balls);
    for (int l = 0; l < n; ++l) {
      CellInfo& i = info[group[l]];
      i.center = balls[l].center;
      i.radius = balls[l].radius;
      // Rounded up to a float: a conversion moves a normal value by at most 2⁻²⁴ of it.
      const double e = balls[l].center_error;
      i.center_error = e < 1e-30 ? 1e-30f : static_cast<float>(e * (1 + 0x1p-20));
      // Without an error bound the rounded center may be far off (ill-conditioned), or not
      // finite: the exact one, where the simplex is not flat.
      if (!std::isfinite(e) && !exact_ball(vertices[l], i) && !std::isfinite(i.center[0]))
        continue;  // flat
      i.long_radius = i.radius / balls[l].shortest_edge >= params.radius_edge_bound;
      i.label_code = 0;
      i.surface_known = false;
      i.finite = true;
    }
    n = 0;
  };
  for (CellId c : cells) {
    info.ensure(std::size_t{c} + 1);
    info[c].finite = false;
    if (st.is_infinite(c)) continue;
    group[n] = c;
    VertexId v[5];
    std::copy(std::begin(st.cell(c).v), std::end(st.cell(c).v), v);
    if (covering.active()) sort_ids(v);
    for (int k = 0; k < 5; ++k) vertices[n][k] = &st.point(v[k]);
    if (++n == 4) measure();
  }
  if (n > 0) measure();
}

domain::Label RefinementState::translate_invariant_label(CellId c) const {
  const CellInfo& own = info[c];
  const auto& st = tri.store();
  // The periods that move c's anchor into the middle sheet; none for a representative, whose
  // own circumball admit() measured from its points in the order of their ids, and none for a
  // pentatope with a box corner, which has no translates.
  const double a = PeriodicCovering::anchor(tri, c);
  const domain::TimePeriod& period = covering.period();
  const double shift = a < period.start ? period.length : -period.length;
  if (covering.in_middle(a) || !covering.in_middle(a + shift)) return oracle.label_at(own.center);
  VertexId v[5];
  std::copy(std::begin(st.cell(c).v), std::end(st.cell(c).v), v);
  sort_ids(v);
  Point4 moved[5];
  const Point4* vertices[4][5];
  for (int k = 0; k < 5; ++k) {
    if (v[k] == delaunay::kInfiniteVertex || st.vertex(v[k]).kind == VertexKind::box)
      return oracle.label_at(own.center);
    moved[k] = st.point(v[k]);
    moved[k][3] += shift;  // exact: times lie on the grid of kTimeQuantum
    vertices[0][k] = &moved[k];
  }
  for (int l = 1; l < 4; ++l) std::copy(vertices[0], vertices[0] + 5, vertices[l]);
  // admit()'s arithmetic on the middle sheet's translate.
  delaunay::Circumball balls[4];
  delaunay::circumballs4(vertices, balls);
  CellInfo middle;
  middle.center = balls[0].center;
  if (!std::isfinite(balls[0].center_error) && !exact_ball(vertices[0], middle) &&
      !std::isfinite(middle.center[0]))
    return oracle.label_at(own.center);
  return oracle.label_at(middle.center);
}

void RefinementState::prepare_concurrent() {
  if (concurrent_ready_) return;
  // Vertex ids: the budget, plus the ids of rolled-back insertions and removed vertices.
  tri.prepare_concurrent(std::max<std::uint64_t>(4 * params.vertex_budget, 1u << 20));
  info.reserve_blocks(std::size_t{delaunay::kNoCell} + 1);
  concurrent_ready_ = true;
}

Point4 RefinementState::centroid_of(CellId c) const {
  Point4 g{};
  for (const Point4& p : simplex_of(c))
    for (int k = 0; k < 4; ++k) g[k] += 0.2 * p[k];
  return g;
}

Point4 RefinementState::clamp_to_box(const Point4& p) const {
  Point4 q;
  for (int k = 0; k < 4; ++k) q[k] = std::clamp(p[k], box[0][k], box[1][k]);
  return q;
}

void RefinementState::decide(const CellId* cells, int count, const Point4& p,
                             std::int8_t* verdict) const {
  for (int k = 0; k < count; ++k) {
    const CellInfo& i = info[cells[k]];
    verdict[k] = i.finite ? static_cast<std::int8_t>(
                                delaunay::ball_verdict(i.center, i.radius, i.center_error, p))
                          : 0;
  }
}

}  // namespace mesh4d::refine
