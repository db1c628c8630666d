#include "mesh/mesh_slice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "mesh/periodic_mesh.h"
#include "support/parallel_parts.h"

namespace mesh4d::mesh {
namespace {

using P3 = std::array<double, 3>;

constexpr std::size_t kMinShare = 4096;  // pentatopes per thread, at least

double signed_volume6(const P3& a, const P3& b, const P3& c, const P3& d) {
  const P3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const P3 v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const P3 w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
         u[2] * (v[0] * w[1] - v[1] * w[0]);
}

// Six times the volume of a pentatope's section by the hyperplane t = `time`, which its time
// span contains: the edges from the corners below t to those at or above it, cut at t. A
// pentatope whose top is at t has a section (a facet on the plane is the section of the
// pentatope below it, as in slice_mesh); one whose bottom is at t has none.
double section_volume6(const Mesh4& mesh, const std::array<std::uint32_t, 5>& cell, double time) {
  std::array<std::uint32_t, 5> below{}, above{};
  int nb = 0, na = 0;
  for (auto v : cell) (mesh.vertices[v][3] < time ? below[nb++] : above[na++]) = v;
  const auto cut = [&](std::uint32_t a, std::uint32_t b) {
    const Point4& p0 = mesh.vertices[a];
    const Point4& p1 = mesh.vertices[b];
    const double s = (time - p0[3]) / (p1[3] - p0[3]);
    return P3{p0[0] + s * (p1[0] - p0[0]), p0[1] + s * (p1[1] - p0[1]),
              p0[2] + s * (p1[2] - p0[2])};
  };
  if (nb == 1 || na == 1) {
    std::array<P3, 4> q;
    for (int j = 0; j < 4; ++j) q[j] = nb == 1 ? cut(below[0], above[j]) : cut(below[j], above[0]);
    return std::abs(signed_volume6(q[0], q[1], q[2], q[3]));
  }
  std::array<P3, 3> a, b;  // the prism's two triangles
  for (int j = 0; j < 3; ++j) {
    a[j] = nb == 2 ? cut(below[0], above[j]) : cut(below[j], above[0]);
    b[j] = nb == 2 ? cut(below[1], above[j]) : cut(below[j], above[1]);
  }
  return std::abs(signed_volume6(a[0], a[1], a[2], b[2])) +
         std::abs(signed_volume6(a[0], a[1], b[2], b[1])) +
         std::abs(signed_volume6(a[0], b[1], b[2], b[0]));
}

// Builds a slice: one point per crossing edge, shared by every pentatope around that edge.
class Slicer {
 public:
  Slicer(const Mesh4& mesh, double time) : mesh_(mesh), time_(time) {
    slice_.time = time;
    double lo = time, hi = time;
    for (const auto& p : mesh.vertices) lo = std::min(lo, p[3]), hi = std::max(hi, p[3]);
    snap_ = 1e-9 * (hi - lo);
  }

  // Corners within a billionth of the mesh's time span of the plane are taken as on it: a
  // corner a rounding error away would otherwise leave needle tetrahedra (volumes around 1e-15)
  // whose orientation no reader computes reliably.
  bool on_plane(std::uint32_t v) const { return std::abs(mesh_.vertices[v][3] - time_) <= snap_; }
  bool below(std::uint32_t v) const { return mesh_.vertices[v][3] < time_ && !on_plane(v); }

  // The point where edge (lo, hi) meets the plane: lo below, hi above. A corner exactly on the
  // plane is that corner, whatever edge reaches it, so sections stay conforming there too.
  std::uint32_t cut(std::uint32_t lo, std::uint32_t hi) {
    const Point4& p = mesh_.vertices[lo];
    const Point4& q = mesh_.vertices[hi];
    const bool corner = on_plane(hi);
    const std::uint64_t key = corner ? (std::uint64_t(hi) << 32 | hi)
                                     : (std::uint64_t(std::min(lo, hi)) << 32 | std::max(lo, hi));
    const auto [it, fresh] =
        index_.try_emplace(key, static_cast<std::uint32_t>(slice_.points.size()));
    if (fresh) {
      if (corner) {
        slice_.points.push_back({q[0], q[1], q[2]});
      } else {
        const double s = (time_ - p[3]) / (q[3] - p[3]);
        slice_.points.push_back(
            {p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]), p[2] + s * (q[2] - p[2])});
      }
    }
    return it->second;
  }

  void add_tetrahedron(std::array<std::uint32_t, 4> t, Label label, std::uint32_t pentatope) {
    // Two cuts through one corner on the plane are one point: a flat section.
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (t[i] == t[j]) return;
    const auto& pt = slice_.points;
    const double v = signed_volume6(pt[t[0]], pt[t[1]], pt[t[2]], pt[t[3]]);
    if (v == 0) return;  // flat
    if (v < 0) std::swap(t[2], t[3]);
    slice_.tetrahedra.push_back(t);
    slice_.labels.push_back(label);
    slice_.pentatopes.push_back(pentatope);
  }

  void add_triangle(const std::array<std::uint32_t, 3>& t, const BoundaryTetrahedron& f) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return;
    slice_.triangles.push_back(t);
    slice_.triangle_labels.push_back({f.inner, f.outer});
    slice_.triangle_pentatopes.push_back(f.pentatope);
  }

  void add_pentatope(std::uint32_t index) {
    std::array<std::uint32_t, 5> lo, hi;
    int nl = 0, nh = 0;
    for (std::uint32_t v : mesh_.pentatopes[index]) (below(v) ? lo[nl++] : hi[nh++]) = v;
    if (nl == 0 || nh == 0) return;
    const Label label = mesh_.labels[index];
    if (nl == 1 || nh == 1) {
      // A tetrahedron: the four edges from the lone corner.
      std::array<std::uint32_t, 4> t;
      for (int j = 0; j < 4; ++j) t[j] = nl == 1 ? cut(lo[0], hi[j]) : cut(lo[j], hi[0]);
      add_tetrahedron(t, label, index);
      return;
    }
    // A triangular prism: a_j = cut(lone0, many_j), b_j = cut(lone1, many_j).
    std::array<std::uint32_t, 3> a, b;
    for (int j = 0; j < 3; ++j) {
      a[j] = nl == 2 ? cut(lo[0], hi[j]) : cut(lo[j], hi[0]);
      b[j] = nl == 2 ? cut(lo[1], hi[j]) : cut(lo[j], hi[1]);
    }
    split_prism(a, b, label, index);
  }

  // Dompierre et al.'s rule: each quad's diagonal goes through its smallest point index, which
  // two neighbors sharing the quad agree on. Rotated so that a[0] is the prism's smallest index,
  // the diagonals of the two quads through a[0] start there; the third decides between the two
  // decompositions.
  void split_prism(std::array<std::uint32_t, 3> a, std::array<std::uint32_t, 3> b, Label label,
                   std::uint32_t pentatope) {
    const auto lowest_a = std::min_element(a.begin(), a.end());
    const auto lowest_b = std::min_element(b.begin(), b.end());
    if (*lowest_b < *lowest_a) std::swap(a, b);
    const int m = static_cast<int>(std::min_element(a.begin(), a.end()) - a.begin());
    std::rotate(a.begin(), a.begin() + m, a.end());
    std::rotate(b.begin(), b.begin() + m, b.end());
    if (std::min(a[1], b[2]) < std::min(a[2], b[1])) {
      add_tetrahedron({a[0], a[1], a[2], b[2]}, label, pentatope);
      add_tetrahedron({a[0], a[1], b[2], b[1]}, label, pentatope);
    } else {
      add_tetrahedron({a[0], a[1], a[2], b[1]}, label, pentatope);
      add_tetrahedron({a[0], a[2], b[1], b[2]}, label, pentatope);
    }
    add_tetrahedron({a[0], b[1], b[2], b[0]}, label, pentatope);
  }

  void add_boundary(const BoundaryTetrahedron& f) {
    // Each interface between two labels is listed from both sides: keep the higher label's.
    if (f.outer != 0 && f.inner < f.outer) return;
    std::array<std::uint32_t, 4> lo, hi;
    int nl = 0, nh = 0;
    for (std::uint32_t v : f.vertices) (below(v) ? lo[nl++] : hi[nh++]) = v;
    if (nl == 0 || nh == 0) return;
    if (nl == 1 || nh == 1) {
      std::array<std::uint32_t, 3> t;
      for (int j = 0; j < 3; ++j) t[j] = nl == 1 ? cut(lo[0], hi[j]) : cut(lo[j], hi[0]);
      add_triangle(t, f);
      return;
    }
    // A quad, in cyclic order, split on the diagonal through its smallest index (as the prisms).
    const std::array<std::uint32_t, 4> q{cut(lo[0], hi[0]), cut(lo[0], hi[1]), cut(lo[1], hi[1]),
                                         cut(lo[1], hi[0])};
    const int m = static_cast<int>(std::min_element(q.begin(), q.end()) - q.begin());
    const int s = m % 2;  // the diagonal q[s]–q[s + 2]
    add_triangle({q[s], q[s + 1], q[s + 2]}, f);
    add_triangle({q[s], q[s + 2], q[(s + 3) % 4]}, f);
  }

  SliceMesh take() { return std::move(slice_); }

 private:
  const Mesh4& mesh_;
  const double time_;
  double snap_;
  SliceMesh slice_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;  // edge (or corner) -> point
};

}  // namespace

SliceMesh slice_mesh(const Mesh4& mesh, double time, bool with_boundary) {
  if (mesh.periodic()) {
    // The cycle unrolled: every pentatope's class is cut once at the instant within the period.
    SliceMesh slice = slice_mesh(unrolled(mesh), wrapped_time(mesh, time), with_boundary);
    slice.time = time;
    for (auto* list : {&slice.pentatopes, &slice.triangle_pentatopes})
      for (std::uint32_t& p : *list) p %= static_cast<std::uint32_t>(mesh.pentatopes.size());
    return slice;
  }
  Slicer slicer(mesh, time);
  for (std::size_t i = 0; i < mesh.pentatopes.size(); ++i)
    slicer.add_pentatope(static_cast<std::uint32_t>(i));
  if (with_boundary)
    for (const BoundaryTetrahedron& f : mesh.boundary) slicer.add_boundary(f);
  return slicer.take();
}

double tetrahedron_volume(const SliceMesh& slice, std::size_t i) {
  const auto& t = slice.tetrahedra[i];
  const auto& p = slice.points;
  return signed_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) / 6;
}

std::vector<std::map<Label, double>> slice_volumes(const Mesh4& mesh,
                                                   const std::vector<double>& times,
                                                   unsigned threads) {
  if (mesh.periodic()) {
    // Each instant within the period, in ascending order, on the unrolled cycle.
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t i = 0; i < times.size(); ++i)
      order.emplace_back(wrapped_time(mesh, times[i]), i);
    std::sort(order.begin(), order.end());
    std::vector<double> wrapped;
    for (const auto& o : order) wrapped.push_back(o.first);
    std::vector<std::map<Label, double>> at = slice_volumes(unrolled(mesh), wrapped, threads);
    std::vector<std::map<Label, double>> volumes(times.size());
    for (std::size_t k = 0; k < order.size(); ++k) volumes[order[k].second] = std::move(at[k]);
    return volumes;
  }
  // The labels numbered densely, so that each part sums into a flat table of times × labels.
  std::vector<std::uint32_t> slot(std::size_t{std::numeric_limits<Label>::max()} + 1, 0);
  std::vector<Label> label_of;
  for (const Label l : mesh.labels)
    if (slot[l] == 0) label_of.push_back(l), slot[l] = static_cast<std::uint32_t>(label_of.size());
  const std::size_t width = label_of.size();
  const unsigned parts = support::parts_for(mesh.pentatopes.size(), kMinShare, threads);
  // Per part: the sections' volumes, and whether any pentatope was cut there (a label is listed
  // at a time where it has a section, even a flat one).
  std::vector<std::vector<double>> volume_sum(parts);
  std::vector<std::vector<char>> cut_at(parts);
  support::run_parts(parts, [&](unsigned part) {
    std::vector<double>& sum = volume_sum[part];
    std::vector<char>& cut_here = cut_at[part];
    sum.assign(times.size() * width, 0);
    cut_here.assign(times.size() * width, 0);
    const auto [begin, end] = support::part_range(mesh.pentatopes.size(), part, parts);
    for (std::size_t p = begin; p < end; ++p) {
      const auto& cell = mesh.pentatopes[p];
      double lo = mesh.vertices[cell[0]][3], hi = lo;
      for (auto v : cell)
        lo = std::min(lo, mesh.vertices[v][3]), hi = std::max(hi, mesh.vertices[v][3]);
      for (auto it = std::upper_bound(times.begin(), times.end(), lo);
           it != times.end() && *it <= hi; ++it) {
        const std::size_t k =
            static_cast<std::size_t>(it - times.begin()) * width + slot[mesh.labels[p]] - 1;
        sum[k] += section_volume6(mesh, cell, *it) / 6;
        cut_here[k] = 1;
      }
    }
  });
  std::vector<std::map<Label, double>> volumes(times.size());
  for (std::size_t t = 0; t < times.size(); ++t)
    for (std::size_t l = 0; l < width; ++l) {
      bool cut = false;
      double volume = 0;
      for (unsigned part = 0; part < parts; ++part) {
        cut = cut || cut_at[part][t * width + l];
        volume += volume_sum[part][t * width + l];
      }
      if (cut) volumes[t][label_of[l]] = volume;
    }
  return volumes;
}

std::map<Label, double> slice_volumes(const Mesh4& mesh, double time) {
  const SliceMesh slice = slice_mesh(mesh, time, false);
  std::map<Label, double> volume;
  for (std::size_t i = 0; i < slice.tetrahedra.size(); ++i)
    volume[slice.labels[i]] += tetrahedron_volume(slice, i);
  return volume;
}

}  // namespace mesh4d::mesh
