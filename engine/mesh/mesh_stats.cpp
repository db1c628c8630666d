#include "mesh/mesh_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "delaunay/geometry.h"

namespace mesh4d::mesh {
namespace {

// Welford's running mean and variance: stable for millions of values.
struct Running {
  std::uint64_t n = 0;
  double mean = 0, m2 = 0;
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  void add(double x) {
    ++n;
    const double d = x - mean;
    mean += d / double(n);
    m2 += d * (x - mean);
    min = std::min(min, x);
    max = std::max(max, x);
  }
  Distribution result() const {
    if (n == 0) return {};
    return {min, max, mean, std::sqrt(m2 / double(n))};
  }
};

}  // namespace

MeshStats compute_stats(const Mesh4& mesh) {
  MeshStats stats;
  stats.vertices = mesh.vertices.size();
  stats.pentatopes = mesh.pentatopes.size();
  stats.boundary_tetrahedra = mesh.boundary.size();
  stats.normalized_volume_histogram.assign(kHistogramBins, 0);
  Running ratio, volume;
  double shortest = std::numeric_limits<double>::infinity();
  for (const auto& p : mesh.pentatopes) {
    delaunay::Simplex4 s;
    for (int i = 0; i < 5; ++i) s[i] = mesh.vertices[p[i]];
    const double edge = delaunay::shortest_edge(s);
    shortest = std::min(shortest, edge);
    const double radius = delaunay::circumradius(s);  // once: both measures need it
    ratio.add(radius / edge);
    const double v = delaunay::normalized_volume(s, radius);
    volume.add(v);
    const int bin = std::clamp(static_cast<int>(v * kHistogramBins), 0, kHistogramBins - 1);
    ++stats.normalized_volume_histogram[bin];
  }
  stats.shortest_edge = mesh.pentatopes.empty() ? 0 : shortest;
  stats.radius_edge_ratio = ratio.result();
  stats.normalized_volume = volume.result();
  return stats;
}

}  // namespace mesh4d::mesh
