#include "mesh/periodic_mesh.h"

#include <gtest/gtest.h>

#include "mesh/mesh_slice.h"
#include "mesh/topology_certificate.h"
#include "test_meshes.h"

namespace mesh4d::mesh {
namespace {

TEST(PeriodicMesh, TheGluedBoxIsAClosedCylinderInTime) {
  Mesh4 m = periodic_kuhn_box(2, 3, 4);
  // Its boundary glued: only the faces along x, y and z; the two ends in time are one.
  const Mesh4 g = glued(m);
  for (const auto& [f, owners] : facet_owners(g))
    if (owners.size() == 1) m.boundary.push_back({f, owners[0], 1, 0});
  const std::vector<std::uint32_t> id = glued_vertex_ids(m);
  for (const auto& b : m.boundary)
    for (std::uint32_t v : b.vertices) EXPECT_LT(v, 24u);
  EXPECT_EQ(id[28], 4u);
  const TopologyCertificate c = certify_topology(m);
  ASSERT_EQ(c.labels.size(), 1u);
  EXPECT_TRUE(c.manifold());
  EXPECT_EQ(c.labels[0].components, 1u);
  EXPECT_NEAR(c.labels[0].volume, 72.0, 1e-12);
  // Without the glue its ends in time are a boundary nobody listed.
  Mesh4 open = m;
  open.periodic_twins.clear();
  open.period = 0;
  EXPECT_FALSE(certify_topology(open).manifold());
}

TEST(PeriodicMesh, EveryInstantIsCutAtItsPlaceInThePeriod) {
  Mesh4 m = periodic_kuhn_box(2, 3, 4);
  // The last layer's top corners lie at the period's end, glued to the first layer's bottom.
  EXPECT_DOUBLE_EQ(wrapped_time(m, 3.25), 0.25);
  EXPECT_DOUBLE_EQ(wrapped_time(m, 3), 0);
  EXPECT_DOUBLE_EQ(wrapped_time(m, -5.5), 0.5);
  const Mesh4 u = unrolled(m);
  EXPECT_FALSE(u.periodic());
  EXPECT_EQ(u.pentatopes.size(), 2 * m.pentatopes.size());
  EXPECT_EQ(u.vertices.size(), m.vertices.size() + 24);  // t = -3 ... -1: the copies
  for (double t : {0.0, 0.25, 1.0, 2.75, 2.99, 3.0, 3.2, -7.3}) {
    const auto v = slice_volumes(m, t);
    ASSERT_EQ(v.size(), 1u) << t;
    EXPECT_NEAR(v.at(1), 24.0, 1e-9) << t;
    const SliceMesh s = slice_mesh(m, t, false);
    double total = 0;
    for (std::size_t i = 0; i < s.tetrahedra.size(); ++i) total += tetrahedron_volume(s, i);
    EXPECT_NEAR(total, 24.0, 1e-9) << t;
    for (std::uint32_t p : s.pentatopes) EXPECT_LT(p, m.pentatopes.size());
  }
  const auto many = slice_volumes(m, std::vector<double>{0.75, -0.25, 3.4, 0.1});
  for (const auto& v : many) EXPECT_NEAR(v.at(1), 24.0, 1e-9);
}

}  // namespace
}  // namespace mesh4d::mesh
