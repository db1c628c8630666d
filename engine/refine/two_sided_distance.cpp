#include "refine/two_sided_distance.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <unordered_map>

#include "domain/periodic_time.h"
#include "mesh/periodic_mesh.h"
#include "support/parallel_parts.h"
#include "support/parallel_sort.h"

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
  TetrahedronGrid(const mesh::Mesh4& mesh, unsigned threads) : mesh_(mesh) {
    if (mesh.boundary.empty()) return;
    // Cells as large as a tetrahedron's mean extent along each axis (space and time differ):
    // each tetrahedron lies in a few cells and each cell holds a few tetrahedra.
    Point4 extent{};
    for (const auto& b : mesh.boundary) {
      const auto bb = box(b);
      for (int a = 0; a < 4; ++a) extent[a] += bb[1][a] - bb[0][a];
    }
    const double widest = *std::max_element(extent.begin(), extent.end());
    for (int a = 0; a < 4; ++a)
      cell_[a] = std::max(1e-9, std::max(extent[a], widest / 4) / double(mesh.boundary.size()));
    smallest_cell_ = *std::min_element(cell_.begin(), cell_.end());
    for (std::uint32_t i = 0; i < mesh.boundary.size(); ++i) {
      const auto bb = box(mesh.boundary[i]);
      std::array<long, 4> lo{}, hi{};
      for (int a = 0; a < 4; ++a) lo[a] = cell_of(bb[0][a], a), hi[a] = cell_of(bb[1][a], a);
      for (long t = lo[3]; t <= hi[3]; ++t)
        for (long z = lo[2]; z <= hi[2]; ++z)
          for (long y = lo[1]; y <= hi[1]; ++y)
            for (long x = lo[0]; x <= hi[0]; ++x) cells_.push_back({key({x, y, z, t}), i});
      for (int a = 0; a < 4; ++a)
        low_[a] = std::min(low_[a], lo[a]), high_[a] = std::max(high_[a], hi[a]);
    }
    support::parallel_sort(cells_, threads);
    for (std::size_t i = 0; i < cells_.size();) {
      std::size_t j = i;
      while (j < cells_.size() && cells_[j].first == cells_[i].first) ++j;
      ranges_.emplace(cells_[i].first, std::pair{i, j});
      i = j;
    }
  }

  // The distance from p to the nearest boundary tetrahedron with `label` on one side.
  double nearest(const Point4& p, domain::Label label) const {
    if (cells_.empty()) return kInfinity;
    // Boxes of cells around p that cover a ball of radius `reach`, doubled until the nearest
    // tetrahedron found lies within it (or the box holds every cell). In a box, each candidate
    // gets a lower bound (its bounding box) and an upper one (its nearest vertex); exact
    // distances are taken nearest bound first, while a candidate can still win.
    std::vector<std::pair<double, std::uint32_t>> candidates;
    for (double reach = smallest_cell_ / 4;; reach *= 2) {
      std::array<long, 4> lo{}, hi{};
      bool everything = true;
      for (int a = 0; a < 4; ++a) {
        lo[a] = std::max(low_[a], cell_of(p[a] - reach, a));
        hi[a] = std::min(high_[a], cell_of(p[a] + reach, a));
        everything = everything && lo[a] == low_[a] && hi[a] == high_[a];
      }
      candidates.clear();
      double best = kInfinity;
      for (long t = lo[3]; t <= hi[3]; ++t)
        for (long z = lo[2]; z <= hi[2]; ++z)
          for (long y = lo[1]; y <= hi[1]; ++y)
            for (long x = lo[0]; x <= hi[0]; ++x)
              add_candidates({x, y, z, t}, p, label, &candidates, &best);
      std::sort(candidates.begin(), candidates.end());
      for (const auto& [lower, index] : candidates) {
        if (lower >= best) break;
        std::array<Point4, 4> v{};
        for (int k = 0; k < 4; ++k) v[k] = mesh_.vertices[mesh_.boundary[index].vertices[k]];
        best = std::min(best, distance_to_tetrahedron(p, v));
      }
      if (best <= reach || everything) return best;
    }
  }

 private:
  // The cell's tetrahedra with `label` on a side, each with the distance to its bounding box
  // (a lower bound); `bound` falls to the distance to their nearest vertex (an upper one).
  void add_candidates(const std::array<long, 4>& cell, const Point4& p, domain::Label label,
                      std::vector<std::pair<double, std::uint32_t>>* out, double* bound) const {
    const auto range = ranges_.find(key(cell));
    if (range == ranges_.end()) return;
    for (std::size_t i = range->second.first; i < range->second.second; ++i) {
      const auto& b = mesh_.boundary[cells_[i].second];
      if (b.inner != label && b.outer != label) continue;
      const auto bb = box(b);
      double squared = 0;
      for (int a = 0; a < 4; ++a) {
        const double gap = std::max({0.0, bb[0][a] - p[a], p[a] - bb[1][a]});
        squared += gap * gap;
      }
      const double lower = std::sqrt(squared);
      if (lower >= *bound) continue;
      for (auto v : b.vertices) *bound = std::min(*bound, distance(p, mesh_.vertices[v]));
      out->emplace_back(lower, cells_[i].second);
    }
  }

  std::array<Point4, 2> box(const mesh::BoundaryTetrahedron& b) const {
    std::array<Point4, 2> bb{mesh_.vertices[b.vertices[0]], mesh_.vertices[b.vertices[0]]};
    for (auto v : b.vertices)
      for (int a = 0; a < 4; ++a)
        bb[0][a] = std::min(bb[0][a], mesh_.vertices[v][a]),
        bb[1][a] = std::max(bb[1][a], mesh_.vertices[v][a]);
    return bb;
  }
  long cell_of(double x, int axis) const { return long(std::floor(x / cell_[axis])); }
  static std::uint64_t key(const std::array<long, 4>& c) {
    std::uint64_t k = 0;
    for (long x : c) k = k * 0x10000 + std::uint64_t(x + 0x8000) % 0x10000;
    return k;
  }
  const mesh::Mesh4& mesh_;
  Point4 cell_{1, 1, 1, 1};
  double smallest_cell_ = 1;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cells_;                     // sorted by cell
  std::unordered_map<std::uint64_t, std::pair<std::size_t, std::size_t>> ranges_;  // in cells_
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

namespace {

// Both sides: the image's faces from the voxels of frames [first_frame, first_frame + frames)
// to the tetrahedra of `searched`; `sampled`'s tetrahedra, their centroids placed by `place`,
// to the image's faces.
std::vector<TwoSidedDistance> measure(const mesh::Mesh4& sampled, const mesh::Mesh4& searched,
                                      const domain::LabelImage4& image, std::size_t first_frame,
                                      std::size_t frames,
                                      const std::function<Point4(Point4)>& place,
                                      std::size_t max_samples, unsigned threads) {
  const auto& d = image.dims();
  const std::size_t frame_voxels = d[0] * d[1] * d[2];
  constexpr std::size_t kLabels = std::size_t{std::numeric_limits<domain::Label>::max()} + 1;
  // Faces between a voxel and its +1 neighbour along each axis, counted per label (twice over
  // the image: the first pass sets each label's stride, the second picks the samples).
  std::vector<std::size_t> faces(kLabels, 0), seen(kLabels, 0);
  const auto each_face = [&](auto on_face) {
    const std::array<std::size_t, 4> stride{1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
    std::array<std::size_t, 4> v{0, 0, 0, first_frame};
    for (std::size_t i = first_frame * frame_voxels; i < (first_frame + frames) * frame_voxels;
         ++i) {
      const domain::Label here = image.at(i);
      for (int a = 0; a < 4; ++a) {
        if (v[a] + 1 >= d[a]) continue;  // closed images have background at the border
        const domain::Label there = image.at(i + stride[a]);
        if (here != there) on_face(v, a, here, there);
      }
      for (int a = 0; a < 4 && ++v[a] == d[a]; ++a) v[a] = 0;
    }
  };
  each_face([&](const auto&, int, domain::Label here, domain::Label there) {
    ++faces[here];
    ++faces[there];
  });
  std::vector<std::size_t> tetrahedra(kLabels, 0), taken(kLabels, 0);
  for (const auto& b : sampled.boundary)
    for (domain::Label l : {b.inner, b.outer}) ++tetrahedra[l];
  // The samples, picked in order on one thread; their distances, on the threads.
  struct Sample {
    domain::Label label;
    bool from_image;  // a face centre (image → mesh), or a tetrahedron's centroid
    Point4 point;
    double distance = 0;
  };
  std::vector<Sample> samples;
  each_face(
      [&](const std::array<std::size_t, 4>& v, int a, domain::Label here, domain::Label there) {
        for (domain::Label l : {here, there}) {
          if (!l || seen[l]++ % std::max<std::size_t>(1, faces[l] / max_samples) != 0) continue;
          Point4 centre = image.voxel_center(v[0], v[1], v[2], v[3]);
          centre[a] += 0.5 * image.spacing()[a];
          samples.push_back({l, true, centre});
        }
      });
  for (const auto& b : sampled.boundary)
    for (domain::Label l : {b.inner, b.outer}) {
      if (!l || taken[l]++ % std::max<std::size_t>(1, tetrahedra[l] / max_samples) != 0) continue;
      Point4 centroid{};
      for (auto v : b.vertices)
        for (int k = 0; k < 4; ++k) centroid[k] += 0.25 * sampled.vertices[v][k];
      samples.push_back({l, false, place(centroid)});
    }
  const TetrahedronGrid grid(searched, threads);
  const unsigned parts = support::parts_for(samples.size(), 64, threads);
  support::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = support::part_range(samples.size(), part, parts);
    for (std::size_t i = begin; i < end; ++i) {
      Sample& s = samples[i];
      if (s.from_image)
        s.distance = tetrahedra[s.label] ? grid.nearest(s.point, s.label) : kInfinity;
      else
        s.distance = distance_to_label_faces(s.point, image, s.label);
    }
  });
  std::map<domain::Label, TwoSidedDistance> by_label;
  for (const Sample& s : samples) {
    TwoSidedDistance& entry = by_label[s.label];
    entry.label = s.label;
    add(s.from_image ? entry.image_to_mesh : entry.mesh_to_image, s.distance);
  }
  std::vector<TwoSidedDistance> out;
  for (auto& [label, entry] : by_label) {
    for (SidedDistance* s : {&entry.mesh_to_image, &entry.image_to_mesh})
      if (s->samples) s->mean /= double(s->samples);
    out.push_back(entry);
  }
  return out;
}

}  // namespace

std::vector<TwoSidedDistance> two_sided_distances(const mesh::Mesh4& mesh,
                                                  const domain::LabelImage4& image,
                                                  std::size_t max_samples, unsigned threads) {
  if (!mesh.periodic())
    return measure(
        mesh, mesh, image, 0, image.dims()[3], [](Point4 p) { return p; }, max_samples, threads);
  // The cycle tiled: its middle copy's faces, those across its last frame into the next copy's
  // first included, to the unrolled mesh; the mesh's samples at their place in the period.
  const domain::LabelImage4 tiled = domain::tile_cycle(image);
  return measure(
      mesh, mesh::unrolled(mesh), tiled, image.dims()[3], image.dims()[3],
      [&](Point4 p) {
        p[3] = mesh::wrapped_time(mesh, p[3]);
        return p;
      },
      max_samples, threads);
}

}  // namespace mesh4d::refine
