// The exports read back: MFEM and libMeshb text parsed by their documented layout (sections,
// counts, 0- or 1-based indices, positive orientation), VTK XML by its element counts. The real
// VTK reader checks the .vtu files in tests/python/vtu_slices_test.py.
#include <gtest/gtest.h>

#include <regex>
#include <sstream>
#include <string>

#include "delaunay/geometry.h"
#include "mesh/fem_export.h"
#include "mesh/mesh_slice.h"
#include "mesh/test_meshes.h"
#include "mesh/vtu_writer.h"

namespace mesh4d::mesh {
namespace {

// A Kuhn box, half of it label 2, with its hull and the interface from both sides.
Mesh4 two_label_box() {
  Mesh4 m = kuhn_box(2, 1, 1);
  for (std::size_t i = 0; i < m.labels.size(); i += 3) m.labels[i] = 2;
  add_hull(m);
  add_interfaces(m);
  // Mixed orientations, as the refiner gives them.
  for (std::size_t i = 0; i < m.pentatopes.size(); i += 2)
    std::swap(m.pentatopes[i][0], m.pentatopes[i][1]);
  return m;
}

std::size_t listed_once(const Mesh4& m) {
  std::size_t n = 0;
  for (const auto& f : m.boundary) n += f.outer == 0 || f.inner > f.outer;
  return n;
}

// Reads "keyword\nN\n" and positions the stream after it.
std::size_t section(std::istringstream& in, const std::string& keyword) {
  std::string word;
  while (in >> word)
    if (word == keyword) {
      std::size_t n = 0;
      in >> n;
      return n;
    }
  ADD_FAILURE() << "no section " << keyword;
  return 0;
}

double volume_of(const std::vector<Point4>& points, const std::array<std::uint32_t, 5>& v) {
  delaunay::Simplex4 s;
  for (int k = 0; k < 5; ++k) s[k] = points[v[k]];
  return delaunay::signed_volume(s);
}

TEST(MfemExport, SectionsCountsAttributesAndPositiveOrientation) {
  const Mesh4 m = two_label_box();
  const std::string text = mfem_mesh(m, 7);
  ASSERT_EQ(text.rfind("MFEM mesh v1.0\n", 0), 0u);
  std::istringstream in(text);
  EXPECT_EQ(section(in, "dimension"), 4u);
  std::istringstream vin(text);
  const std::size_t nv = section(vin, "vertices");
  ASSERT_EQ(nv, m.vertices.size());
  int dim = 0;
  vin >> dim;
  ASSERT_EQ(dim, 4);
  std::vector<Point4> points(nv);
  for (auto& p : points) vin >> p[0] >> p[1] >> p[2] >> p[3];
  EXPECT_EQ(points, m.vertices);

  const std::size_t ne = section(in, "elements");
  ASSERT_EQ(ne, m.pentatopes.size());
  for (std::size_t i = 0; i < ne; ++i) {
    int attribute = 0, geometry = 0;
    std::array<std::uint32_t, 5> v;
    in >> attribute >> geometry >> v[0] >> v[1] >> v[2] >> v[3] >> v[4];
    EXPECT_EQ(attribute, m.labels[i]);
    EXPECT_EQ(geometry, 7);
    EXPECT_GT(volume_of(points, v), 0) << "element " << i;
  }
  const std::size_t nb = section(in, "boundary");
  EXPECT_EQ(nb, listed_once(m));
  const auto interfaces = boundary_interfaces(m);
  ASSERT_EQ(interfaces.size(), 3u);  // 1|background, 2|background, 2|1
  for (std::size_t i = 0; i < nb; ++i) {
    int attribute = 0, geometry = 0;
    std::uint32_t v[4];
    in >> attribute >> geometry >> v[0] >> v[1] >> v[2] >> v[3];
    EXPECT_GE(attribute, 1);
    EXPECT_LE(attribute, static_cast<int>(interfaces.size()));
    EXPECT_EQ(geometry, kMfemTetrahedron);
    for (auto x : v) EXPECT_LT(x, nv);
  }
  EXPECT_NE(mfem_mesh(m, 8).find("\n2 8 "), std::string::npos) << "the geometry code is an option";
}

TEST(MfemExport, APeriodicMeshComesWithMakePeriodicsVertexMap) {
  const Mesh4 m = periodic_kuhn_box(1, 1, 1);
  EXPECT_NE(mfem_mesh(m).find("# periodic in time: period 3 from t = 0"), std::string::npos);
  std::istringstream map(mfem_periodic_vertex_map(m));
  std::vector<std::uint32_t> v2v;
  for (std::uint32_t v; map >> v;) v2v.push_back(v);
  ASSERT_EQ(v2v.size(), m.vertices.size());
  for (std::uint32_t v = 0; v < 24; ++v) EXPECT_EQ(v2v[v], v);
  for (std::uint32_t v = 24; v < 32; ++v) EXPECT_EQ(v2v[v], v - 24);
  EXPECT_EQ(mfem_periodic_vertex_map(kuhn_box(1, 1, 1)), "");
}

TEST(MeshbExport, KeywordsOneBasedIndicesAndReferences) {
  const Mesh4 m = two_label_box();
  const std::string text = meshb_mesh(m);
  std::istringstream in(text);
  EXPECT_EQ(section(in, "MeshVersionFormatted"), 2u);
  EXPECT_EQ(section(in, "Dimension"), 4u);
  const std::size_t nv = section(in, "Vertices");
  ASSERT_EQ(nv, m.vertices.size());
  std::vector<Point4> points(nv);
  for (auto& p : points) {
    int ref;
    in >> p[0] >> p[1] >> p[2] >> p[3] >> ref;
  }
  EXPECT_EQ(points, m.vertices);
  const std::size_t nt = section(in, "Tetrahedra");
  EXPECT_EQ(nt, listed_once(m));
  for (std::size_t i = 0; i < nt; ++i) {
    std::uint32_t v[4];
    int ref;
    in >> v[0] >> v[1] >> v[2] >> v[3] >> ref;
    for (auto x : v) {
      EXPECT_GE(x, 1u);
      EXPECT_LE(x, nv);
    }
    EXPECT_GE(ref, 1);
  }
  const std::size_t np = section(in, "Pentatopes");
  ASSERT_EQ(np, m.pentatopes.size());
  for (std::size_t i = 0; i < np; ++i) {
    std::array<std::uint32_t, 5> v;
    int ref;
    in >> v[0] >> v[1] >> v[2] >> v[3] >> v[4] >> ref;
    for (auto& x : v) --x;
    EXPECT_EQ(ref, m.labels[i]);
    EXPECT_GT(volume_of(points, v), 0);
  }
  std::string end;
  in >> end;
  EXPECT_EQ(end, "End");
}

TEST(VtuExport, CountsMatchTheSlice) {
  const Mesh4 m = two_label_box();
  const SliceMesh s = slice_mesh(m, 0.3, true);
  const std::string volume = slice_vtu(m, s);
  const std::string piece = "NumberOfPoints=\"" + std::to_string(s.points.size()) +
                            "\" NumberOfCells=\"" + std::to_string(s.tetrahedra.size()) + "\"";
  EXPECT_NE(volume.find(piece), std::string::npos);
  for (const char* name : {"label", "pentatope", "radius_edge_ratio", "normalized_volume"})
    EXPECT_NE(volume.find("Name=\"" + std::string(name) + "\""), std::string::npos) << name;
  const std::string boundary = slice_boundary_vtu(s);
  EXPECT_NE(boundary.find("NumberOfCells=\"" + std::to_string(s.triangles.size()) + "\""),
            std::string::npos);
  const std::string pvd = pvd_collection({{0.5, "a.vtu"}, {1.5, "b.vtu"}});
  EXPECT_NE(pvd.find("timestep=\"1.5\" part=\"0\" file=\"b.vtu\""), std::string::npos);
}

}  // namespace
}  // namespace mesh4d::mesh
