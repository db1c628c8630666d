#include "mesh/mesh_slice.h"

#include <cmath>

namespace mesh4d::mesh {
namespace {

using P3 = std::array<double, 3>;

double tet_volume(const P3& a, const P3& b, const P3& c, const P3& d) {
  const P3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const P3 v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const P3 w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  const double det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                     u[2] * (v[0] * w[1] - v[1] * w[0]);
  return std::abs(det) / 6;
}

// Where edge (p, q), with p and q on opposite sides, crosses t = time.
P3 crossing(const Point4& p, const Point4& q, double time) {
  const double s = (time - p[3]) / (q[3] - p[3]);
  return {p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]), p[2] + s * (q[2] - p[2])};
}

}  // namespace

std::map<Label, double> slice_volumes(const Mesh4& mesh, double time) {
  std::map<Label, double> volume;
  for (std::size_t i = 0; i < mesh.pentatopes.size(); ++i) {
    // Split the corners by side; a corner exactly on the plane counts as above, which only
    // turns a degenerate section into a flat (zero-volume) one.
    std::array<const Point4*, 5> below, above;
    int nb = 0, na = 0;
    for (auto v : mesh.pentatopes[i]) {
      const Point4& p = mesh.vertices[v];
      (p[3] < time ? below[nb++] : above[na++]) = &p;
    }
    if (nb == 0 || na == 0) continue;
    const auto& lone = nb < na ? below : above;  // the side with fewer corners
    const auto& many = nb < na ? above : below;
    const int n_lone = std::min(nb, na);
    double v = 0;
    if (n_lone == 1) {
      // A tetrahedron: the four edges from the lone corner.
      v = tet_volume(crossing(*lone[0], *many[0], time), crossing(*lone[0], *many[1], time),
                     crossing(*lone[0], *many[2], time), crossing(*lone[0], *many[3], time));
    } else {
      // A triangular prism (convex): triangles a_j = cut(lone0, many_j), b_j = cut(lone1,
      // many_j), split into three tetrahedra.
      std::array<P3, 3> a, b;
      for (int j = 0; j < 3; ++j)
        a[j] = crossing(*lone[0], *many[j], time), b[j] = crossing(*lone[1], *many[j], time);
      v = tet_volume(a[0], a[1], a[2], b[0]) + tet_volume(a[1], a[2], b[0], b[1]) +
          tet_volume(a[2], b[0], b[1], b[2]);
    }
    volume[mesh.labels[i]] += v;
  }
  return volume;
}

}  // namespace mesh4d::mesh
