#include "mesh/mesh_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "delaunay/geometry.h"
#include "support/parallel_parts.h"

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
  // Chan et al.'s pairwise update: the same moments as if o's values had been added here.
  void merge(const Running& o) {
    if (o.n == 0) return;
    if (n == 0) {
      *this = o;
      return;
    }
    const double total = double(n + o.n);
    const double d = o.mean - mean;
    mean += d * double(o.n) / total;
    m2 += o.m2 + d * d * double(n) * double(o.n) / total;
    n += o.n;
    min = std::min(min, o.min);
    max = std::max(max, o.max);
  }
  Distribution result() const {
    if (n == 0) return {};
    return {min, max, mean, std::sqrt(m2 / double(n))};
  }
};

// What one contiguous share of the pentatopes measures.
struct Part {
  Running ratio, volume;
  double shortest = std::numeric_limits<double>::infinity();
  std::vector<std::uint64_t> histogram = std::vector<std::uint64_t>(kHistogramBins, 0);
};

void measure(const Mesh4& mesh, std::size_t begin, std::size_t end, Part& part) {
  for (std::size_t k = begin; k < end; ++k) {
    const auto& p = mesh.pentatopes[k];
    delaunay::Simplex4 s;
    for (int i = 0; i < 5; ++i) s[i] = mesh.vertices[p[i]];
    const double edge = delaunay::shortest_edge(s);
    part.shortest = std::min(part.shortest, edge);
    const double radius = delaunay::circumradius(s);  // once: both measures need it
    part.ratio.add(radius / edge);
    const double v = delaunay::normalized_volume(s, radius);
    part.volume.add(v);
    const int bin = std::clamp(static_cast<int>(v * kHistogramBins), 0, kHistogramBins - 1);
    ++part.histogram[bin];
  }
}

}  // namespace

MeshStats compute_stats(const Mesh4& mesh, unsigned threads) {
  MeshStats stats;
  stats.vertices = mesh.vertices.size() - mesh.periodic_twins.size();  // glued at the seam
  stats.pentatopes = mesh.pentatopes.size();
  stats.boundary_tetrahedra = mesh.boundary.size();
  // A share of fewer than kMinShare pentatopes is not worth a thread.
  constexpr std::size_t kMinShare = 4096;
  const unsigned parts = support::parts_for(mesh.pentatopes.size(), kMinShare, threads);
  std::vector<Part> measured(parts);
  support::run_parts(parts, [&](unsigned p) {
    const auto [begin, end] = support::part_range(mesh.pentatopes.size(), p, parts);
    measure(mesh, begin, end, measured[p]);
  });
  // Merged in part order: the result depends on the thread count only in the last bits of the
  // means and deviations.
  Part all = std::move(measured[0]);
  for (unsigned p = 1; p < parts; ++p) {
    all.ratio.merge(measured[p].ratio);
    all.volume.merge(measured[p].volume);
    all.shortest = std::min(all.shortest, measured[p].shortest);
    for (int b = 0; b < kHistogramBins; ++b) all.histogram[b] += measured[p].histogram[b];
  }
  stats.normalized_volume_histogram = std::move(all.histogram);
  stats.shortest_edge = mesh.pentatopes.empty() ? 0 : all.shortest;
  stats.radius_edge_ratio = all.ratio.result();
  stats.normalized_volume = all.volume.result();
  return stats;
}

}  // namespace mesh4d::mesh
