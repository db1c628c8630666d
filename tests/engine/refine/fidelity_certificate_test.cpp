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

void expect_same(const FidelityCertificate& a, const FidelityCertificate& b) {
  ASSERT_EQ(a.labels.size(), b.labels.size());
  for (std::size_t i = 0; i < a.labels.size(); ++i) {
    const LabelFidelity &x = a.labels[i], &y = b.labels[i];
    SCOPED_TRACE("label " + std::to_string(x.label));
    EXPECT_EQ(x.label, y.label);
    EXPECT_EQ(x.mesh_pieces, y.mesh_pieces);
    EXPECT_EQ(x.touching_pieces, y.touching_pieces);
    EXPECT_EQ(x.image_pieces, y.image_pieces);
    EXPECT_EQ(x.non_manifold_vertices, y.non_manifold_vertices);
    EXPECT_EQ(x.non_manifold_edges, y.non_manifold_edges);
    EXPECT_EQ(x.non_manifold_triangles, y.non_manifold_triangles);
    EXPECT_EQ(x.boundary_list_mismatches, y.boundary_list_mismatches);
    EXPECT_EQ(x.volume, y.volume);
    EXPECT_EQ(x.worst_frame_error, y.worst_frame_error);
    EXPECT_EQ(x.distance_samples, y.distance_samples);
    EXPECT_EQ(x.mesh_to_image_max, y.mesh_to_image_max);
    EXPECT_EQ(x.mesh_to_image_mean, y.mesh_to_image_mean);
    EXPECT_EQ(x.image_to_mesh_max, y.image_to_mesh_max);
    EXPECT_EQ(x.image_to_mesh_mean, y.image_to_mesh_mean);
  }
}

// On the job's threads (sorts split and merged, link checks and distances shared out): the
// same certificate, to the last bit. The hypersphere's mesh is large enough to be split; the
// coarse ventricle's has non-manifold boundary simplices to count.
TEST(FidelityCertificate, ThreadsGiveTheSameCertificate) {
  const Meshed sphere = meshed(domain::hypersphere_phantom({24, 24, 24, 24}, {1, 1, 1, 1}, 9), 2);
  const Meshed ventricle =
      meshed(domain::beating_ventricle_phantom({40, 40, 16, 6}, {4.4, 4.4, 16, 3}), 8);
  for (const Meshed* m : {&sphere, &ventricle}) {
    const FidelityCertificate one = certify(m->mesh, m->image, 1);
    for (unsigned threads : {2u, 3u, 4u}) {
      SCOPED_TRACE(std::to_string(threads) + " threads");
      expect_same(certify(m->mesh, m->image, threads), one);
    }
  }
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
