// Cross-section volumes of a 4D mesh: the Kuhn triangulation of a box (24 pentatopes, cut into
// tetrahedra and prisms at every t inside) must give the box's 3D volume exactly.
#include "mesh/mesh_slice.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <set>

#include "mesh/test_meshes.h"

namespace mesh4d::mesh {
namespace {

TEST(MeshSlice, KuhnBoxGivesTheBoxVolumeAtEveryInstantInside) {
  const Mesh4 m = kuhn_box(2, 3, 0.5);
  for (double t : {0.01, 0.25, 0.5, 0.77, 0.99}) {
    const auto v = slice_volumes(m, t);
    ASSERT_EQ(v.size(), 1u);
    EXPECT_NEAR(v.at(1), 3.0, 1e-12) << "t = " << t;
  }
  EXPECT_TRUE(slice_volumes(m, -0.1).empty());
  EXPECT_TRUE(slice_volumes(m, 1.1).empty());
}

// The one-pass volumes at many times are the slicer's, time by time: on the Kuhn box with mixed
// labels, at times inside, on its corners' times and outside.
TEST(MeshSlice, VolumesAtManyTimesInOnePassAreTheSlicersOneByOne) {
  Mesh4 m = kuhn_box(2, 3, 0.5);
  for (std::size_t i = 0; i < m.labels.size(); i += 3) m.labels[i] = 2;
  const std::vector<double> times{-0.5, 0.0, 0.01, 0.25, 0.5, 0.77, 0.99, 1.0, 1.5};
  const auto many = slice_volumes(m, times);
  ASSERT_EQ(many.size(), times.size());
  for (std::size_t k = 0; k < times.size(); ++k) {
    const auto one = slice_volumes(m, times[k]);
    for (Label l : {Label{1}, Label{2}}) {
      const double a = one.count(l) ? one.at(l) : 0, b = many[k].count(l) ? many[k].at(l) : 0;
      EXPECT_NEAR(a, b, 1e-12) << "t = " << times[k] << ", label " << l;
    }
  }
  EXPECT_NEAR(many[3].at(1) + many[3].at(2), 3.0, 1e-12);
}

// The unit 4-cube as n⁴ Kuhn boxes (each with its own corners: slice volumes need no conformity).
Mesh4 kuhn_grid(int n) {
  const Mesh4 box = kuhn_box(1.0 / n, 1.0 / n, 1.0 / n);
  Mesh4 m;
  for (int c = 0; c < n * n * n * n; ++c) {
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    const double shift[4] = {double(c % n) / n, double(c / n % n) / n, double(c / n / n % n) / n,
                             double(c / n / n / n)};
    for (Point4 p : box.vertices) {
      for (int a = 0; a < 4; ++a) p[a] = a < 3 ? p[a] + shift[a] : (p[a] + shift[a]) / n;
      m.vertices.push_back(p);
      m.vertex_kinds.push_back(VertexKind::free);
    }
    for (auto cell : box.pentatopes) {
      for (auto& v : cell) v += base;
      m.pentatopes.push_back(cell);
      m.labels.push_back(1);
    }
  }
  return m;
}

// On several threads each part sums its own pentatopes: the volumes are the one thread's, to
// rounding, and every label with a section is listed at every time. 24 × 6⁴ pentatopes make
// several shares of 4,096.
TEST(MeshSlice, VolumesOnSeveralThreadsAreTheOneThreads) {
  Mesh4 m = kuhn_grid(6);
  for (std::size_t i = 0; i < m.labels.size(); i += 5) m.labels[i] = 3;
  for (std::size_t i = 0; i < m.labels.size(); i += 7) m.labels[i] = 9;
  const std::vector<double> times{-0.5, 0.0, 0.03, 0.25, 0.5, 0.5 + 1e-9, 0.97, 1.0};
  const auto one = slice_volumes(m, times, 1);
  const auto four = slice_volumes(m, times, 4);
  ASSERT_EQ(four.size(), one.size());
  for (std::size_t k = 0; k < times.size(); ++k) {
    ASSERT_EQ(four[k].size(), one[k].size()) << "t = " << times[k];
    for (const auto& [l, v] : one[k]) EXPECT_NEAR(four[k].at(l), v, 1e-12) << "label " << l;
  }
  double whole = 0;
  for (const auto& [l, v] : four[3]) whole += v;
  EXPECT_NEAR(whole, 1.0, 1e-12);
  EXPECT_EQ(four[3].size(), 3u);
}

TEST(MeshSlice, LabelsAreKeptApart) {
  Mesh4 m = kuhn_box(1, 1, 1);
  for (std::size_t i = 0; i < m.labels.size(); i += 2) m.labels[i] = 2;
  const auto v = slice_volumes(m, 0.4);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_NEAR(v.at(1) + v.at(2), 1.0, 1e-12);
  EXPECT_GT(v.at(1), 0.1);
  EXPECT_GT(v.at(2), 0.1);
}

// The hull of a mesh: facets in one pentatope only, as background boundary.
using Triangle = std::array<std::uint32_t, 3>;

// Faces of the slice's tetrahedra and how many tetrahedra share each.
std::map<Triangle, int> face_counts(const SliceMesh& s) {
  std::map<Triangle, int> faces;
  for (const auto& t : s.tetrahedra)
    for (int skip = 0; skip < 4; ++skip) {
      Triangle f;
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) f[j++] = t[k];
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  return faces;
}

// A slice is a conforming mesh whose boundary triangles are exactly its faces in one
// tetrahedron (the cut hull), and whose tetrahedra are positively oriented.
void expect_conforming_with_boundary(const Mesh4& m, double t) {
  const SliceMesh s = slice_mesh(m, t, true);
  ASSERT_FALSE(s.tetrahedra.empty());
  std::set<Triangle> open, listed;
  for (const auto& [f, n] : face_counts(s)) {
    EXPECT_LE(n, 2) << "a face in more than two tetrahedra at t = " << t;
    if (n == 1) open.insert(f);
  }
  for (std::size_t i = 0; i < s.tetrahedra.size(); ++i) EXPECT_GT(tetrahedron_volume(s, i), 0);
  for (auto f : s.triangles) {
    std::sort(f.begin(), f.end());
    EXPECT_TRUE(listed.insert(f).second) << "a boundary triangle listed twice";
  }
  EXPECT_EQ(open, listed) << "t = " << t;
}

TEST(MeshSlice, SectionsConformAndTheirBoundaryIsTheCutHull) {
  Mesh4 m = kuhn_box(2, 3, 0.5);
  add_hull(m);
  for (double t : {0.01, 0.25, 0.5, 0.77}) expect_conforming_with_boundary(m, t);
}

TEST(MeshSlice, CornersOnThePlaneAreSharedNotDuplicated) {
  // Two boxes stacked in time; at t = 1 every corner of the cut lies on the plane.
  Mesh4 m = kuhn_box(1, 2, 1);
  const Mesh4 upper = kuhn_box(1, 2, 1);
  const auto offset = static_cast<std::uint32_t>(m.vertices.size());
  for (auto p : upper.vertices) m.vertices.push_back({p[0], p[1], p[2], p[3] + 1});
  for (auto p : upper.pentatopes) {
    for (auto& v : p) v += offset;
    m.pentatopes.push_back(p);
    m.labels.push_back(1);
  }
  m.vertex_kinds.resize(m.vertices.size(), VertexKind::free);
  const SliceMesh s = slice_mesh(m, 1.0, false);
  double volume = 0;
  for (std::size_t i = 0; i < s.tetrahedra.size(); ++i) volume += tetrahedron_volume(s, i);
  EXPECT_NEAR(volume, 2.0, 1e-12);
  EXPECT_EQ(s.points.size(), 8u) << "the eight corners of the box, each once";
}

TEST(MeshSlice, InterfacesBetweenLabelsAreListedOnce) {
  Mesh4 m = kuhn_box(1, 1, 1);
  for (std::size_t i = 0; i < m.labels.size(); i += 2) m.labels[i] = 2;
  add_hull(m);
  add_interfaces(m);
  const SliceMesh s = slice_mesh(m, 0.4, true);
  std::set<Triangle> seen;
  std::size_t interfaces = 0;
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    auto f = s.triangles[i];
    std::sort(f.begin(), f.end());
    EXPECT_TRUE(seen.insert(f).second);
    if (s.triangle_labels[i][1] != 0) {
      EXPECT_EQ(s.triangle_labels[i][0], 2);
      EXPECT_EQ(s.triangle_labels[i][1], 1);
      ++interfaces;
    }
  }
  EXPECT_GT(interfaces, 0u);
}

}  // namespace
}  // namespace mesh4d::mesh
