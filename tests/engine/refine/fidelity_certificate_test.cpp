// The fidelity certificate: the mesh's topology beside the image's pieces and volumes. On the
// hypersphere (one smooth label) it finds no defect and volumes close to the voxels'; on a
// coarse ventricle each label's defect sentence says exactly what its counts say.
#include "refine/fidelity_certificate.h"

#include <gtest/gtest.h>

#include "domain/phantoms.h"
#include "domain/surface_oracle.h"
#include "refine/refiner.h"

namespace mesh4d::refine {
namespace {

struct Meshed {
  domain::LabelImage4 image;
  mesh::Mesh4 mesh;
};

Meshed meshed(domain::LabelImage4 image, double delta) {
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = delta;
  mesh::Mesh4 mesh = refine(oracle, params).mesh;
  return {std::move(image), std::move(mesh)};
}

TEST(FidelityCertificate, TheHypersphereIsOneManifoldPieceOfAboutItsVoxelsVolume) {
  const Meshed m = meshed(domain::hypersphere_phantom({24, 24, 24, 24}, {1, 1, 1, 1}, 9), 2);
  const FidelityCertificate c = certify(m.mesh, m.image);
  ASSERT_EQ(c.labels.size(), 1u);
  const LabelFidelity& l = c.labels[0];
  std::printf("hypersphere: volume %.0f of %.0f voxels; worst frame %+.1f %% at t = %.1f\n",
              l.volume, l.voxel_volume, 100 * l.worst_frame_error, l.worst_frame_time);
  EXPECT_EQ(l.mesh_pieces, 1u);
  EXPECT_EQ(l.image_pieces, 1u);
  EXPECT_TRUE(c.defects().empty());
  EXPECT_NEAR(l.volume / l.voxel_volume, 1.0, 0.1);
  EXPECT_LT(std::abs(l.worst_frame_error), 1.0);
  EXPECT_NE(l.worst_frame_error, 0.0) << "the frames were compared";
}

TEST(FidelityCertificate, EachDefectSentenceSaysWhatItsCountsSay) {
  const Meshed m = meshed(domain::beating_ventricle_phantom({40, 40, 16, 6}, {4.4, 4.4, 16, 3}), 8);
  const FidelityCertificate c = certify(m.mesh, m.image);
  const auto defects = c.defects();
  std::size_t expected = 0;
  for (const LabelFidelity& l : c.labels) {
    const bool defect = l.touching_pieces || l.mesh_pieces != l.image_pieces ||
                        l.non_manifold_vertices || l.non_manifold_edges ||
                        l.non_manifold_triangles || l.boundary_list_mismatches;
    expected += defect;
    bool named = false;
    for (const auto& d : defects)
      named |= d.rfind("label " + std::to_string(l.label) + ":", 0) == 0;
    EXPECT_EQ(named, defect) << "label " << l.label;
    EXPECT_GT(l.voxel_volume, 0);
    EXPECT_GT(l.volume, 0);
  }
  EXPECT_EQ(defects.size(), expected);
  for (const auto& d : defects) std::printf("%s\n", d.c_str());
}

// Both sides of the distance: within about Δ for the refined hypersphere, and a mesh moved by
// 3 units along x is at least about 3 away on both sides (minus the sampling's reach).
TEST(FidelityCertificate, TheTwoSidedDistanceSeesAMeshMovedOffItsImage) {
  Meshed m = meshed(domain::hypersphere_phantom({24, 24, 24, 24}, {1, 1, 1, 1}, 9), 2);
  const LabelFidelity near = certify(m.mesh, m.image).labels.at(0);
  std::printf(
      "hypersphere: mesh to image max %.3f mean %.3f; image to mesh max %.3f mean %.3f "
      "(%zu samples)\n",
      near.mesh_to_image_max, near.mesh_to_image_mean, near.image_to_mesh_max,
      near.image_to_mesh_mean, near.distance_samples);
  EXPECT_GE(near.distance_samples, 500u);
  EXPECT_LT(near.mesh_to_image_max, 2.0);
  EXPECT_LT(near.image_to_mesh_max, 2.0);
  EXPECT_GT(near.image_to_mesh_mean, 0.0) << "voxel faces are a staircase, the mesh is not";
  for (auto& v : m.mesh.vertices) v[0] += 3;
  const LabelFidelity moved = certify(m.mesh, m.image).labels.at(0);
  std::printf("moved by 3: mesh to image max %.3f; image to mesh max %.3f\n",
              moved.mesh_to_image_max, moved.image_to_mesh_max);
  EXPECT_GT(moved.mesh_to_image_max, 2.5);
  EXPECT_GT(moved.image_to_mesh_max, 2.5);
  EXPECT_GT(moved.image_to_mesh_mean, near.image_to_mesh_mean + 0.5);
}

}  // namespace
}  // namespace mesh4d::refine
