// Cross-section volumes of a 4D mesh: the Kuhn triangulation of a box (24 pentatopes, cut into
// tetrahedra and prisms at every t inside) must give the box's 3D volume exactly.
#include "mesh/mesh_slice.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

namespace mesh4d::mesh {
namespace {

// The box [0,sx]×[0,sy]×[0,sz]×[0,1] as 24 Kuhn simplices (one per order of the axes), label 1.
Mesh4 kuhn_box(double sx, double sy, double sz) {
  Mesh4 m;
  for (int c = 0; c < 16; ++c) {
    m.vertices.push_back(
        {(c & 1) * sx, ((c >> 1) & 1) * sy, ((c >> 2) & 1) * sz, double((c >> 3) & 1)});
    m.vertex_kinds.push_back(VertexKind::free);
  }
  std::array<int, 4> axes{0, 1, 2, 3};
  do {
    std::array<std::uint32_t, 5> p{};
    std::uint32_t corner = 0;
    for (int k = 0; k < 4; ++k) p[k + 1] = corner |= 1u << axes[k];
    m.pentatopes.push_back(p);
    m.labels.push_back(1);
  } while (std::next_permutation(axes.begin(), axes.end()));
  return m;
}

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

TEST(MeshSlice, LabelsAreKeptApart) {
  Mesh4 m = kuhn_box(1, 1, 1);
  for (std::size_t i = 0; i < m.labels.size(); i += 2) m.labels[i] = 2;
  const auto v = slice_volumes(m, 0.4);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_NEAR(v.at(1) + v.at(2), 1.0, 1e-12);
  EXPECT_GT(v.at(1), 0.1);
  EXPECT_GT(v.at(2), 0.1);
}

}  // namespace
}  // namespace mesh4d::mesh
