#include "refine/facet_sag.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "delaunay/geometry.h"
#include "delaunay/predicates.h"
#include "domain/periodic_time.h"
#include "mesh/periodic_mesh.h"
#include "support/parallel_parts.h"

namespace mesh4d::refine {

namespace {

using Vec = std::array<double, 4>;

// 4/5: the mean depth of a paraboloid under an inscribed regular tetrahedron, over the depth at
// its circumcenter (E|x|² over a simplex centered at 0 is Σ|vᵢ|² / ((n+1)(n+2)) = ρ²/5 for n = 3).
constexpr double kMeanDepthRatio = 1.0 - 1.0 / 5.0;
constexpr std::size_t kMinShare = 4096;  // facets or pentatopes per thread, at least
constexpr int kHalvings = 4;             // then a move that still spoils a pentatope is dropped
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

// Whether a pentatope with corners moved is still as good as the refinement left it: positively
// oriented (exactly), no sliver it was not, and no radius-edge ratio past the bound it was not.
struct Quality {
  double tau = 0, rho = 0;  // normalized volume, radius-edge ratio
};

Quality quality(const delaunay::Simplex4& s) {
  return {delaunay::normalized_volume(s), delaunay::radius_edge_ratio(s)};
}

bool still_good(const Quality& before, const delaunay::Simplex4& after,
                const RefineParams& params) {
  if (delaunay::orient4(after[0], after[1], after[2], after[3], after[4]) <= 0) return false;
  const Quality now = quality(after);
  if (now.tau < params.sliver_bound && now.tau < before.tau) return false;
  return now.rho < params.radius_edge_bound || now.rho <= before.rho;
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
  std::vector<Vec> offset(nv, Vec{});
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
    moving.push_back(v);
  }
  // The pentatopes a move touches, and the moves' scales, halved where one spoils a pentatope.
  std::vector<double> scale(nv, 0);
  for (std::uint32_t v : moving) scale[v] = 1;
  std::vector<std::uint32_t> touched;
  for (std::uint32_t p = 0; p < mesh.pentatopes.size(); ++p)
    for (std::uint32_t v : mesh.pentatopes[p])
      if (scale[glued[v]] > 0) {
        touched.push_back(p);
        break;
      }
  const auto place = [&] {
    for (std::uint32_t v = 0; v < nv; ++v) {
      const double k = scale[glued[v]];
      for (int a = 0; a < 4; ++a) mesh.vertices[v][a] = before[v][a] + k * offset[glued[v]][a];
    }
  };
  // Each round checks the pentatopes whose corners moved differently in the last one.
  std::vector<Quality> was(touched.size());
  std::vector<char> spoiled(touched.size()), changed(nv, 1);
  std::vector<std::uint32_t> check(touched.size());
  for (std::uint32_t i = 0; i < touched.size(); ++i) check[i] = i;
  for (int round = 0; !check.empty(); ++round) {
    place();
    const unsigned check_parts = support::parts_for(check.size(), kMinShare, threads);
    support::run_parts(check_parts, [&](unsigned p) {
      const auto [begin, end] = support::part_range(check.size(), p, check_parts);
      for (std::size_t c = begin; c < end; ++c) {
        const std::uint32_t i = check[c];
        delaunay::Simplex4 is;
        for (int k = 0; k < 5; ++k) {
          const std::uint32_t v = mesh.pentatopes[touched[i]][k];
          is[k] = mesh.vertices[v];
        }
        if (round == 0) {
          delaunay::Simplex4 original;
          for (int k = 0; k < 5; ++k) original[k] = before[mesh.pentatopes[touched[i]][k]];
          was[i] = quality(original);
        }
        spoiled[i] = !still_good(was[i], is, params);
      }
    });
    std::fill(changed.begin(), changed.end(), 0);
    for (std::uint32_t i : check) {
      if (!spoiled[i]) continue;
      for (std::uint32_t v : mesh.pentatopes[touched[i]]) {
        double& k = scale[glued[v]];
        if (k == 0) continue;
        k = round < kHalvings ? k / 2 : 0;
        changed[glued[v]] = 1;
      }
    }
    check.clear();
    for (std::uint32_t i = 0; i < touched.size(); ++i)
      for (std::uint32_t v : mesh.pentatopes[touched[i]])
        if (changed[glued[v]]) {
          check.push_back(i);
          break;
        }
  }
  for (std::uint32_t v : moving) {
    report.held += scale[v] < 1;
    if (scale[v] == 0) continue;
    ++report.moved;
    report.largest_offset =
        std::max(report.largest_offset, scale[v] * std::sqrt(dot(offset[v], offset[v])));
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace mesh4d::refine
