// Points on ∂Ω already in the mesh, in a hash grid of cell size Δ, answering R1's question: is
// there a feature vertex within Δ of z?
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "delaunay/point4.h"

namespace mesh4d::refine {

class FeatureIndex {
 public:
  explicit FeatureIndex(double cell) : cell_(cell) {}

  void add(const Point4& p) { grid_[key(cell_of(p))].push_back(p); }

  /// Whether some added point lies strictly within distance r (≤ the cell size) of p.
  bool any_within(const Point4& p, double r) const {
    // Only the grid cells that the box around the ball overlaps: 1 to 16 of them (of the 81
    // around p), fewer the smaller r.
    std::array<long, 4> lo, hi;
    for (int a = 0; a < 4; ++a) {
      lo[a] = long(std::floor((p[a] - r) / cell_));
      hi[a] = long(std::floor((p[a] + r) / cell_));
    }
    const double r2 = r * r;
    std::array<long, 4> n;
    for (n[3] = lo[3]; n[3] <= hi[3]; ++n[3])
      for (n[2] = lo[2]; n[2] <= hi[2]; ++n[2])
        for (n[1] = lo[1]; n[1] <= hi[1]; ++n[1])
          for (n[0] = lo[0]; n[0] <= hi[0]; ++n[0]) {
            const auto it = grid_.find(key(n));
            if (it == grid_.end()) continue;
            for (const Point4& q : it->second) {
              double d2 = 0;
              for (int a = 0; a < 4; ++a) d2 += (p[a] - q[a]) * (p[a] - q[a]);
              if (d2 < r2) return true;
            }
          }
    return false;
  }

 private:
  std::array<long, 4> cell_of(const Point4& p) const {
    return {long(std::floor(p[0] / cell_)), long(std::floor(p[1] / cell_)),
            long(std::floor(p[2] / cell_)), long(std::floor(p[3] / cell_))};
  }
  static std::uint64_t key(const std::array<long, 4>& c) {
    std::uint64_t h = 0;
    for (long v : c) h = h * 0x100000001B3ull ^ static_cast<std::uint64_t>(v + (1 << 20));
    return h;
  }
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<Point4>> grid_;
};

}  // namespace mesh4d::refine
