// Point sets for triangulation tests: random, clustered, exact lattices, exactly co-spherical.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "delaunay/point4.h"

namespace mesh4d::testing {

inline std::vector<Point4> random_points(std::size_t n, std::uint64_t seed, double lo = 0,
                                         double hi = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Point4> pts(n);
  for (auto& p : pts) p = {u(rng), u(rng), u(rng), u(rng)};
  return pts;
}

/// Tight Gaussian clusters around a few random centers.
inline std::vector<Point4> clustered_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 0.01);
  std::vector<Point4> centers(5);
  for (auto& c : centers) c = {u(rng), u(rng), u(rng), u(rng)};
  std::vector<Point4> pts(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Point4& c = centers[i % centers.size()];
    pts[i] = {c[0] + g(rng), c[1] + g(rng), c[2] + g(rng), c[3] + g(rng)};
  }
  return pts;
}

/// Every point of the lattice {0..k-1}⁴ times `step`: maximally degenerate input.
inline std::vector<Point4> lattice(int k, double step = 1.0) {
  std::vector<Point4> pts;
  for (int t = 0; t < k; ++t)
    for (int z = 0; z < k; ++z)
      for (int y = 0; y < k; ++y)
        for (int x = 0; x < k; ++x) pts.push_back({x * step, y * step, z * step, t * step});
  return pts;
}

/// Integer points with x²+y²+z²+t² = r2 exactly (all co-spherical), plus the 16 corners of
/// [-1, 1]⁴ (co-spherical on another sphere with the same center).
inline std::vector<Point4> cospherical_points(int r2) {
  std::vector<Point4> pts;
  const int r = static_cast<int>(std::sqrt(double(r2)));
  for (int x = -r; x <= r; ++x)
    for (int y = -r; y <= r; ++y)
      for (int z = -r; z <= r; ++z)
        for (int t = -r; t <= r; ++t)
          if (x * x + y * y + z * z + t * t == r2)
            pts.push_back({double(x), double(y), double(z), double(t)});
  for (int i = 0; i < 16; ++i)
    pts.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0, i & 8 ? 1.0 : -1.0});
  return pts;
}

}  // namespace mesh4d::testing
