#include "refine/two_sided_distance.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
#include <map>

namespace mesh4d::refine {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The distance from p to a tetrahedron in 4D. The closest point lies inside some face (a vertex,
// an edge, a triangle or the tetrahedron itself), where it is the projection of p onto that
// face's affine hull with non-negative barycentric coordinates; every such projection is a
// point of the tetrahedron, so the least of them is the distance.
double distance_to_tetrahedron(const Point4& p, const std::array<Point4, 4>& v) {
  double best = kInfinity;
  for (unsigned mask = 1; mask < 16; ++mask) {
    std::array<int, 4> corner{};
    int m = 0;
    for (int k = 0; k < 4; ++k)
      if (mask & (1u << k)) corner[m++] = k;
    const Point4& base = v[corner[0]];
    std::array<Point4, 3> e{};
    for (int j = 1; j < m; ++j)
      for (int c = 0; c < 4; ++c) e[j - 1][c] = v[corner[j]][c] - base[c];
    // Normal equations G·c = b of the projection, by Gaussian elimination (at most 3×3).
    const int n = m - 1;
    double g[3][4] = {};
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j)
        for (int c = 0; c < 4; ++c) g[i][j] += e[i][c] * e[j][c];
      for (int c = 0; c < 4; ++c) g[i][3] += e[i][c] * (p[c] - base[c]);
    }
    bool singular = false;
    for (int i = 0; i < n && !singular; ++i) {
      int pivot = i;
      for (int r = i + 1; r < n; ++r)
        if (std::abs(g[r][i]) > std::abs(g[pivot][i])) pivot = r;
      if (std::abs(g[pivot][i]) < 1e-300) {
        singular = true;
        break;
      }
      std::swap(g[i], g[pivot]);
      for (int r = 0; r < n; ++r) {
        if (r == i) continue;
        const double f = g[r][i] / g[i][i];
        for (int c = i; c < 4; ++c) g[r][c] -= f * g[i][c];
      }
    }
    if (singular) continue;
    double first = 1;
    Point4 q = base;
    bool inside = true;
    for (int i = 0; i < n; ++i) {
      const double c = g[i][3] / g[i][i];
      inside = inside && c >= -1e-12;
      first -= c;
      for (int k = 0; k < 4; ++k) q[k] += c * e[i][k];
    }
    if (inside && first >= -1e-12) best = std::min(best, distance(p, q));
  }
  return best;
}

// The distance from p to the nearest voxel face between `label` and any other label (the
// image's outside counts as background), searching boxes of voxels that double in size until
// the nearest face found lies within the box.
double distance_to_label_faces(const Point4& p, const domain::LabelImage4& image,
                               domain::Label label) {
  const auto& d = image.dims();
  const auto& s = image.spacing();
  const domain::Vec4 at = image.to_index(p);
  const double largest = *std::max_element(s.begin(), s.end());
  double diagonal = 0;
  for (int a = 0; a < 4; ++a) diagonal += std::pow(double(d[a]) * s[a], 2);
  for (double radius = largest; radius < 4 * std::sqrt(diagonal); radius *= 2) {
    std::array<long, 4> lo{}, hi{};
    for (int a = 0; a < 4; ++a) {
      lo[a] = std::max<long>(0, long(std::floor(at[a] - radius / s[a])) - 1);
      hi[a] = std::min<long>(long(d[a]) - 1, long(std::ceil(at[a] + radius / s[a])) + 1);
      if (lo[a] > hi[a]) lo[a] = hi[a] + 1;  // the box misses the image
    }
    double best = kInfinity;
    for (long t = lo[3]; t <= hi[3]; ++t)
      for (long z = lo[2]; z <= hi[2]; ++z)
        for (long y = lo[1]; y <= hi[1]; ++y)
          for (long x = lo[0]; x <= hi[0]; ++x) {
            const std::array<long, 4> v{x, y, z, t};
            if (image.at(x, y, z, t) != label) continue;
            const Point4 centre = image.voxel_center(x, y, z, t);
            for (int a = 0; a < 4; ++a)
              for (int side : {-1, 1}) {
                std::array<long, 4> n = v;
                n[a] += side;
                const bool outside = n[a] < 0 || n[a] >= long(d[a]);
                if (!outside && image.at(n[0], n[1], n[2], n[3]) == label) continue;
                // The face: the voxel's box with axis a fixed on that side.
                double squared = 0;
                for (int b = 0; b < 4; ++b) {
                  const double gap = b == a
                                         ? p[b] - (centre[b] + 0.5 * side * s[b])
                                         : std::max(0.0, std::abs(p[b] - centre[b]) - 0.5 * s[b]);
                  squared += gap * gap;
                }
                best = std::min(best, squared);
              }
          }
    if (std::sqrt(best) <= radius) return std::sqrt(best);
  }
  return kInfinity;
}

// Boundary tetrahedra bucketed by a uniform grid over their bounding boxes (sorted cell keys),
// searched ring by ring around a point.
class TetrahedronGrid {
 public:
  explicit TetrahedronGrid(const mesh::Mesh4& mesh) : mesh_(mesh) {
    if (mesh.boundary.empty()) return;
    double extent = 0;
    for (const auto& b : mesh.boundary) extent += box(b)[1][0] - box(b)[0][0];
    cell_ = std::max(1e-9, 2 * extent / double(mesh.boundary.size()));
    for (std::uint32_t i = 0; i < mesh.boundary.size(); ++i) {
      const auto bb = box(mesh.boundary[i]);
      std::array<long, 4> lo{}, hi{};
      for (int a = 0; a < 4; ++a) lo[a] = cell_of(bb[0][a]), hi[a] = cell_of(bb[1][a]);
      for (long t = lo[3]; t <= hi[3]; ++t)
        for (long z = lo[2]; z <= hi[2]; ++z)
          for (long y = lo[1]; y <= hi[1]; ++y)
            for (long x = lo[0]; x <= hi[0]; ++x) cells_.push_back({key({x, y, z, t}), i});
      for (int a = 0; a < 4; ++a)
        low_[a] = std::min(low_[a], lo[a]), high_[a] = std::max(high_[a], hi[a]);
    }
    std::sort(cells_.begin(), cells_.end());
  }

  // The distance from p to the nearest boundary tetrahedron with `label` on one side.
  double nearest(const Point4& p, domain::Label label) const {
    if (cells_.empty()) return kInfinity;
    std::array<long, 4> c{};
    for (int a = 0; a < 4; ++a) c[a] = cell_of(p[a]);
    long reach = 0;  // rings beyond which no cell holds a tetrahedron
    for (int a = 0; a < 4; ++a)
      reach = std::max({reach, std::abs(c[a] - low_[a]), std::abs(c[a] - high_[a])});
    double best = kInfinity;
    for (long r = 0; r <= reach; ++r) {
      visit_ring(c, r, [&](const std::array<long, 4>& cell) {
        const std::uint64_t k = key(cell);
        for (auto it = std::lower_bound(cells_.begin(), cells_.end(), std::pair{k, 0u});
             it != cells_.end() && it->first == k; ++it) {
          const auto& b = mesh_.boundary[it->second];
          if (b.inner != label && b.outer != label) continue;
          // The tetrahedron's bounding box first: most are farther than the best so far (and a
          // tetrahedron in several cells is measured once where it can still win).
          const auto bb = box(b);
          double squared = 0;
          for (int a = 0; a < 4; ++a) {
            const double gap = std::max({0.0, bb[0][a] - p[a], p[a] - bb[1][a]});
            squared += gap * gap;
          }
          if (squared >= best * best) continue;
          std::array<Point4, 4> v{};
          for (int j = 0; j < 4; ++j) v[j] = mesh_.vertices[b.vertices[j]];
          best = std::min(best, distance_to_tetrahedron(p, v));
        }
      });
      // Cells of the next ring lie at least r cells from p's own cell.
      if (best <= double(r) * cell_) break;
    }
    return best;
  }

 private:
  std::array<Point4, 2> box(const mesh::BoundaryTetrahedron& b) const {
    std::array<Point4, 2> bb{mesh_.vertices[b.vertices[0]], mesh_.vertices[b.vertices[0]]};
    for (auto v : b.vertices)
      for (int a = 0; a < 4; ++a)
        bb[0][a] = std::min(bb[0][a], mesh_.vertices[v][a]),
        bb[1][a] = std::max(bb[1][a], mesh_.vertices[v][a]);
    return bb;
  }
  long cell_of(double x) const { return long(std::floor(x / cell_)); }
  static std::uint64_t key(const std::array<long, 4>& c) {
    std::uint64_t k = 0;
    for (long x : c) k = k * 0x10000 + std::uint64_t(x + 0x8000) % 0x10000;
    return k;
  }
  template <typename Visit>
  static void visit_ring(const std::array<long, 4>& c, long r, Visit visit) {
    for (long t = -r; t <= r; ++t)
      for (long z = -r; z <= r; ++z)
        for (long y = -r; y <= r; ++y)
          for (long x = -r; x <= r; ++x)
            if (std::max({std::abs(x), std::abs(y), std::abs(z), std::abs(t)}) == r)
              visit({c[0] + x, c[1] + y, c[2] + z, c[3] + t});
  }

  const mesh::Mesh4& mesh_;
  double cell_ = 1;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cells_;
  std::array<long, 4> low_{LONG_MAX, LONG_MAX, LONG_MAX, LONG_MAX};
  std::array<long, 4> high_{LONG_MIN, LONG_MIN, LONG_MIN, LONG_MIN};
};

void add(SidedDistance& s, double d) {
  if (!std::isfinite(d)) return;
  s.max = std::max(s.max, d);
  s.mean += d;
  ++s.samples;
}

}  // namespace

std::vector<TwoSidedDistance> two_sided_distances(const mesh::Mesh4& mesh,
                                                  const domain::LabelImage4& image,
                                                  std::size_t max_samples) {
  std::map<domain::Label, TwoSidedDistance> by_label;
  const auto& d = image.dims();
  // Faces between a voxel and its +1 neighbour along each axis, counted per label (twice over
  // the image: the first pass sets each label's stride, the second samples).
  std::map<domain::Label, std::size_t> faces, seen;
  const auto each_face = [&](auto on_face) {
    for (std::size_t t = 0; t < d[3]; ++t)
      for (std::size_t z = 0; z < d[2]; ++z)
        for (std::size_t y = 0; y < d[1]; ++y)
          for (std::size_t x = 0; x < d[0]; ++x) {
            const domain::Label here = image.at(x, y, z, t);
            const std::array<std::size_t, 4> v{x, y, z, t};
            for (int a = 0; a < 4; ++a) {
              if (v[a] + 1 >= d[a]) continue;  // closed images have background at the border
              std::array<std::size_t, 4> n = v;
              ++n[a];
              const domain::Label there = image.at(n[0], n[1], n[2], n[3]);
              if (here != there) on_face(v, a, here, there);
            }
          }
  };
  each_face([&](const auto&, int, domain::Label here, domain::Label there) {
    if (here) ++faces[here];
    if (there) ++faces[there];
  });
  std::map<domain::Label, std::size_t> tetrahedra, taken;
  for (const auto& b : mesh.boundary)
    for (domain::Label l : {b.inner, b.outer})
      if (l) ++tetrahedra[l];
  const TetrahedronGrid grid(mesh);
  each_face(
      [&](const std::array<std::size_t, 4>& v, int a, domain::Label here, domain::Label there) {
        for (domain::Label l : {here, there}) {
          if (!l || seen[l]++ % std::max<std::size_t>(1, faces[l] / max_samples) != 0) continue;
          Point4 centre = image.voxel_center(v[0], v[1], v[2], v[3]);
          centre[a] += 0.5 * image.spacing()[a];
          TwoSidedDistance& entry = by_label[l];
          entry.label = l;
          if (tetrahedra.count(l)) add(entry.image_to_mesh, grid.nearest(centre, l));
        }
      });

  for (const auto& b : mesh.boundary)
    for (domain::Label l : {b.inner, b.outer}) {
      if (!l || taken[l]++ % std::max<std::size_t>(1, tetrahedra[l] / max_samples) != 0) continue;
      Point4 centroid{};
      for (auto v : b.vertices)
        for (int k = 0; k < 4; ++k) centroid[k] += 0.25 * mesh.vertices[v][k];
      TwoSidedDistance& entry = by_label[l];
      entry.label = l;
      add(entry.mesh_to_image, distance_to_label_faces(centroid, image, l));
    }

  std::vector<TwoSidedDistance> out;
  for (auto& [label, entry] : by_label) {
    for (SidedDistance* s : {&entry.mesh_to_image, &entry.image_to_mesh})
      if (s->samples) s->mean /= double(s->samples);
    out.push_back(entry);
  }
  return out;
}

}  // namespace mesh4d::refine
