#include "refine/facet_sag.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "delaunay/geometry.h"
#include "domain/periodic_time.h"
#include "mesh/periodic_mesh.h"
#include "refine/guarded_moves.h"
#include "support/parallel_parts.h"

namespace mesh4d::refine {

namespace {

using Vec = std::array<double, 4>;

// 4/5: the mean depth of a paraboloid under an inscribed regular tetrahedron, over the depth at
// its circumcenter (E|x|² over a simplex centered at 0 is Σ|vᵢ|² / ((n+1)(n+2)) = ρ²/5 for n = 3).
constexpr double kMeanDepthRatio = 1.0 - 1.0 / 5.0;
constexpr std::size_t kMinShare = 4096;  // facets per thread, at least
constexpr int kFalsePositionSteps = 30;  // at most, to kSagTolerance of the circumradius
constexpr double kSagTolerance = 1e-6;

double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

Vec minus(const Point4& a, const Point4& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]};
}

// One restricted facet's measure: its unit normal from the lower label to the higher, its
// volume, and the signed distance along that normal from its circumcenter to ∂Ω (positive: the
// surface lies on the higher label's side, so the facet cuts into the lower label).
struct FacetSag {
  Vec normal{};
  double volume = 0;
  double sag = 0;
  bool measured = false;
};

FacetSag measure(const mesh::Mesh4& mesh, const mesh::BoundaryTetrahedron& b,
                 const domain::SurfaceOracle& oracle) {
  FacetSag out;
  const delaunay::Tetrahedron4 facet{mesh.vertices[b.vertices[0]], mesh.vertices[b.vertices[1]],
                                     mesh.vertices[b.vertices[2]], mesh.vertices[b.vertices[3]]};
  const Point4& p0 = facet[0];
  Vec n = delaunay::hyperplane_normal(facet);
  const double length = std::sqrt(dot(n, n));
  if (!(length > 0)) return out;
  for (double& c : n) c /= length;
  // Oriented away from the facet's pentatope (inner → outer), then from the lower real label to
  // the higher (a ghost is its real label here, so that both sides of a cap's ridge agree).
  const bool inner_higher = oracle.real_label(b.inner) > oracle.real_label(b.outer);
  const auto& cell = mesh.pentatopes[b.pentatope];
  const auto apex = *std::find_if(cell.begin(), cell.end(), [&](std::uint32_t v) {
    return std::find(b.vertices.begin(), b.vertices.end(), v) == b.vertices.end();
  });
  const bool flip = (dot(n, minus(mesh.vertices[apex], p0)) > 0) != inner_higher;
  if (flip)
    for (double& c : n) c = -c;
  const Point4 center = delaunay::facet_circumcenter(facet);
  const double radius = std::sqrt(dot(minus(center, p0), minus(center, p0)));
  if (!std::isfinite(radius)) return out;
  // The dual Voronoi edge is the line through the circumcenter along the normal; its crossing
  // with the facet's own interface within a circumradius is the surface ball's center.
  const domain::Label hi = inner_higher ? b.inner : b.outer, lo = inner_higher ? b.outer : b.inner;
  const auto cut = [&](double s) {
    Point4 q;
    for (int a = 0; a < 4; ++a) q[a] = center[a] + s * n[a];
    return oracle.cut_value(q, hi, lo);
  };
  double s0 = -radius, s1 = radius, f0 = cut(s0), f1 = cut(s1), sag = s1;
  if ((f0 > 0) == (f1 > 0)) return out;
  // Regula falsi with the Illinois step (the cut function is smooth along the line between voxel
  // planes): a few evaluations where bisection takes thirty.
  for (int i = 0; i < kFalsePositionSteps && std::abs(s1 - s0) > kSagTolerance * radius; ++i) {
    sag = (s0 * f1 - s1 * f0) / (f1 - f0);
    const double f = cut(sag);
    if (f == 0) break;
    if ((f > 0) == (f1 > 0)) {
      f0 /= 2;
    } else {
      s0 = s1, f0 = f1;
    }
    s1 = sag, f1 = f;
  }
  out.normal = n;
  out.volume = length / 6;
  out.sag = sag;
  out.measured = true;
  return out;
}

// The depth a facet's vertices did not move, taken over by those that moved whole, in one more
// guarded move, so that the facet still gives back about the volume its sag cut off: the part of
// an offset the guard held back, and a junction vertex's part (it does not move), 4/5 of the
// facet's own sag. Each facet's missing volume goes to its whole movers in equal shares, as
// depth over each one's facets (weight: their volume). Returns {held, taken} in 4-volume.
std::array<double, 2> spread_held_depth(
    mesh::Mesh4& mesh, const std::vector<std::uint32_t>& glued,
    const std::vector<std::uint32_t>& facets, const std::vector<FacetSag>& sag,
    const std::vector<double>& weight, const std::vector<double>& depth,
    const std::vector<char>& junction, const std::vector<Point4>& offset,
    const std::vector<std::uint32_t>& moving, const std::vector<double>& scale,
    const RefineParams& params) {
  const std::size_t nv = mesh.vertices.size();
  std::vector<double> extra(nv, 0);
  double held = 0;
  for (std::size_t i = 0; i < facets.size(); ++i) {
    if (!sag[i].measured) continue;
    int whole = 0;
    double missing = 0;  // depth, summed over the facet's vertices
    for (std::uint32_t w : mesh.boundary[facets[i]].vertices) {
      const std::uint32_t g = glued[w];
      if (junction[g]) missing += kMeanDepthRatio * sag[i].sag;
      if (depth[g] == 0) continue;
      if (scale[g] == 1)
        ++whole;
      else
        missing += (1 - scale[g]) * depth[g];
    }
    held += std::abs(missing) * sag[i].volume / 4;
    if (whole == 0 || missing == 0) continue;
    for (std::uint32_t w : mesh.boundary[facets[i]].vertices) {
      const std::uint32_t g = glued[w];
      if (depth[g] != 0 && scale[g] == 1) extra[g] += missing * sag[i].volume / (whole * weight[g]);
    }
  }
  std::vector<Point4> more(nv, Point4{});
  std::vector<std::uint32_t> takers;
  for (std::uint32_t v : moving) {
    if (extra[v] == 0) continue;
    // At most as much again as its own depth, so that the boundary stays near ∂Ω everywhere.
    extra[v] = std::clamp(extra[v], -std::abs(depth[v]), std::abs(depth[v]));
    for (int a = 0; a < 4; ++a) more[v][a] = extra[v] * offset[v][a] / depth[v];
    if (mesh.periodic()) more[v][3] = domain::snap_time(more[v][3]);
    takers.push_back(v);
  }
  if (takers.empty()) return {held, 0};
  const std::vector<Point4> now = mesh.vertices;
  const std::vector<double> k = move_guarded(mesh, now, glued, more, takers, nullptr, params).scale;
  double taken = 0;
  for (std::uint32_t v : takers) taken += k[v] * std::abs(extra[v]) * weight[v] / 4;
  return {held, taken};
}

}  // namespace

SagOffset offset_facet_sag(mesh::Mesh4& mesh, const domain::SurfaceOracle& oracle,
                           const RefineParams& params) {
  const auto start = std::chrono::steady_clock::now();
  SagOffset report;
  const std::size_t nv = mesh.vertices.size();
  const std::vector<std::uint32_t> glued = mesh::glued_vertex_ids(mesh);
  const std::vector<Point4> before = mesh.vertices;
  // Which interface each vertex lies on, a time caps' ghost counting as its real label; a vertex
  // on two is a junction and stays. A facet between a label and its ghost is the cap: flat, not
  // measured, and its vertices move within the cap's hyperplane.
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max(), kMany = kNone - 1;
  std::vector<std::uint32_t> interface(nv, kNone);
  std::vector<char> on_cap(nv, 0);
  std::vector<std::uint32_t> facets;  // each measured facet once (both sides are listed)
  for (std::uint32_t i = 0; i < mesh.boundary.size(); ++i) {
    const auto& b = mesh.boundary[i];
    const domain::Label a = oracle.real_label(b.inner), c = oracle.real_label(b.outer);
    if (a == c) {
      for (std::uint32_t v : b.vertices) on_cap[glued[v]] = 1;
      continue;
    }
    const std::uint32_t key = (std::uint32_t{std::min(a, c)} << 16) | std::max(a, c);
    for (std::uint32_t v : b.vertices) {
      std::uint32_t& k = interface[glued[v]];
      k = k == kNone ? key : k == key ? k : kMany;
    }
    if (b.outer == 0 || b.inner > b.outer) facets.push_back(i);
  }
  std::vector<FacetSag> sag(facets.size());
  const unsigned threads = working_threads(params);
  const unsigned parts = support::parts_for(facets.size(), kMinShare, threads);
  support::run_parts(parts, [&](unsigned p) {
    const auto [begin, end] = support::part_range(facets.size(), p, parts);
    for (std::size_t i = begin; i < end; ++i)
      sag[i] = measure(mesh, mesh.boundary[facets[i]], oracle);
  });
  // Each vertex's offset: the facets' volume-weighted mean sag, times the mean-depth ratio,
  // along their volume-weighted normal.
  std::vector<Vec> normal(nv, Vec{});
  std::vector<double> weighted(nv, 0), weight(nv, 0);
  double sag_sum = 0, volume_sum = 0;
  for (std::size_t i = 0; i < facets.size(); ++i) {
    const FacetSag& s = sag[i];
    if (!s.measured) continue;
    ++report.facets;
    sag_sum += std::abs(s.sag) * s.volume, volume_sum += s.volume;
    for (std::uint32_t v : mesh.boundary[facets[i]].vertices) {
      const std::uint32_t g = glued[v];
      for (int a = 0; a < 4; ++a) normal[g][a] += s.volume * s.normal[a];
      weighted[g] += s.volume * s.sag, weight[g] += s.volume;
    }
  }
  report.mean_sag = volume_sum > 0 ? sag_sum / volume_sum : 0;
  std::vector<Point4> offset(nv, Point4{});
  std::vector<double> depth_of(nv, 0);  // signed, along the vertex's normal; 0: stays
  std::vector<std::uint32_t> moving;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (glued[v] != v || weight[v] == 0 || interface[v] >= kMany ||
        mesh.vertex_kinds[v] != mesh::VertexKind::feature)
      continue;
    const double depth = kMeanDepthRatio * weighted[v] / weight[v];
    // In periodic time a vertex within its offset of the seam keeps its time, so that twins stay
    // exact translates and every pentatope keeps its anchor in the period.
    const double reach = std::abs(depth);
    const bool near_seam =
        mesh.periodic() && (std::abs(before[v][3] - mesh.period_start) <= reach ||
                            std::abs(before[v][3] - mesh.period_start - mesh.period) <= reach);
    if (on_cap[v] || near_seam) normal[v][3] = 0;
    const double length = std::sqrt(dot(normal[v], normal[v]));
    if (!(length > 0)) continue;
    for (int a = 0; a < 4; ++a) offset[v][a] = depth * normal[v][a] / length;
    if (mesh.periodic()) offset[v][3] = domain::snap_time(offset[v][3]);
    depth_of[v] = depth;
    moving.push_back(v);
  }
  const std::vector<double> scale =
      move_guarded(mesh, before, glued, offset, moving, nullptr, params).scale;
  std::vector<char> junction(nv, 0);
  for (std::uint32_t v = 0; v < nv; ++v) junction[v] = interface[v] == kMany;
  const auto [held, taken] = spread_held_depth(mesh, glued, facets, sag, weight, depth_of, junction,
                                               offset, moving, scale, params);
  report.held_volume = held;
  report.spread_volume = taken;
  if (params.fit_frame_volumes) {
    InterfaceVertices movers;
    movers.glued = glued;
    for (std::uint32_t v : moving) {
      movers.ids.push_back(v);
      movers.sides.push_back({static_cast<mesh::Label>(interface[v] >> 16),
                              static_cast<mesh::Label>(interface[v] & 0xFFFFu)});
      movers.normals.push_back(normal[v]);
    }
    report.fit = fit_frame_volumes(mesh, oracle, movers, params);
  }
  for (std::uint32_t v : moving) {
    report.held += scale[v] < 1;
    const Vec move = minus(mesh.vertices[v], before[v]);
    if (move == Vec{}) continue;
    ++report.moved;
    report.largest_offset = std::max(report.largest_offset, std::sqrt(dot(move, move)));
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace mesh4d::refine
