// The viewer's slice surfaces: decoded here byte by byte as the browser reads them, they must
// hold the slice's boundary triangles (each interface once), only the points those use, the
// labels on either side, each triangle's pentatope quality, and the mesh's time span.
#include "mesh/slice_surface.h"

#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "delaunay/geometry.h"
#include "mesh/test_meshes.h"

namespace mesh4d::mesh {
namespace {

struct Decoded {
  double time = 0, begin = 0, end = 0;
  std::vector<std::array<float, 3>> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::array<std::uint16_t, 2>> labels;
  std::vector<float> ratio, volume;
};

template <typename T>
T take(const std::string& bytes, std::size_t& at) {
  T value;
  EXPECT_LE(at + sizeof(T), bytes.size());
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  at += sizeof(T);
  return value;
}

Decoded decode(const std::string& bytes) {
  Decoded d;
  EXPECT_EQ(bytes.substr(0, 4), "M4DS");
  std::size_t at = 4;
  EXPECT_EQ(take<std::uint32_t>(bytes, at), 1u);
  d.time = take<double>(bytes, at);
  d.begin = take<double>(bytes, at);
  d.end = take<double>(bytes, at);
  const auto n = take<std::uint32_t>(bytes, at), m = take<std::uint32_t>(bytes, at);
  EXPECT_EQ(at, 40u);
  d.points.resize(n);
  for (auto& p : d.points)
    for (float& c : p) c = take<float>(bytes, at);
  d.triangles.resize(m);
  for (auto& t : d.triangles)
    for (auto& c : t) c = take<std::uint32_t>(bytes, at);
  d.labels.resize(m);
  for (auto& l : d.labels)
    for (auto& c : l) c = take<std::uint16_t>(bytes, at);
  d.ratio.resize(m);
  for (float& x : d.ratio) x = take<float>(bytes, at);
  d.volume.resize(m);
  for (float& x : d.volume) x = take<float>(bytes, at);
  EXPECT_EQ(at, bytes.size()) << "nothing after the last array";
  return d;
}

TEST(SliceSurface, HoldsTheSlicesBoundaryWithItsLabelsQualityAndTimeSpan) {
  Mesh4 m = kuhn_box(2, 3, 0.5);
  for (std::size_t i = 0; i < m.labels.size(); i += 3) m.labels[i] = 2;
  add_hull(m);
  add_interfaces(m);
  const SliceMesh s = slice_mesh(m, 0.4, true);
  ASSERT_FALSE(s.triangles.empty());
  const Decoded d = decode(encode_slice_surface(m, s));
  EXPECT_EQ(d.time, 0.4);
  EXPECT_EQ(d.begin, 0.0);
  EXPECT_EQ(d.end, 1.0);
  ASSERT_EQ(d.triangles.size(), s.triangles.size());
  std::set<std::uint32_t> used;
  for (std::size_t i = 0; i < d.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_LT(d.triangles[i][k], d.points.size());
      used.insert(d.triangles[i][k]);
      // The same corner as the slice's, as floats.
      const auto& want = s.points[s.triangles[i][k]];
      for (int a = 0; a < 3; ++a)
        EXPECT_EQ(d.points[d.triangles[i][k]][a], static_cast<float>(want[a]));
    }
    EXPECT_EQ(d.labels[i][0], s.triangle_labels[i][0]);
    EXPECT_EQ(d.labels[i][1], s.triangle_labels[i][1]);
    delaunay::Simplex4 p;
    for (int k = 0; k < 5; ++k) p[k] = m.vertices[m.pentatopes[s.triangle_pentatopes[i]][k]];
    EXPECT_FLOAT_EQ(d.ratio[i], static_cast<float>(delaunay::radius_edge_ratio(p)));
    EXPECT_FLOAT_EQ(d.volume[i], static_cast<float>(delaunay::normalized_volume(p)));
    EXPECT_GT(d.volume[i], 0);
  }
  EXPECT_EQ(used.size(), d.points.size()) << "only the points the triangles use";
  // The boundary's own pentatope: each triangle was cut from the boundary tetrahedron's inner
  // side, whose label is the triangle's inner label.
  for (std::size_t i = 0; i < s.triangles.size(); ++i)
    EXPECT_EQ(m.labels[s.triangle_pentatopes[i]], s.triangle_labels[i][0]);
}

// A periodic mesh's vertices reach past its period (the later twins of pentatopes that cross
// the seam; one stands for them here): its span is the period.
TEST(SliceSurface, PeriodicMeshesSpanTheirPeriod) {
  Mesh4 m = periodic_kuhn_box(1, 1, 1, 3);
  add_hull(m);
  m.vertices.push_back({0, 0, 0, 3.4});
  m.vertex_kinds.push_back(VertexKind::free);
  const SliceMesh s = slice_mesh(m, 4.5, true);  // wraps to 1.5
  const Decoded d = decode(encode_slice_surface(m, s));
  EXPECT_EQ(d.begin, 0.0);
  EXPECT_EQ(d.end, 3.0);
  EXPECT_EQ(d.triangles.size(), s.triangles.size());
  EXPECT_FALSE(d.triangles.empty());
  for (std::size_t i = 0; i < s.triangles.size(); ++i)
    EXPECT_LT(s.triangle_pentatopes[i], m.pentatopes.size());
}

}  // namespace
}  // namespace mesh4d::mesh
