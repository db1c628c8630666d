// Faithful open ends: with the time caps' ghost frames no ghost is left, the mesh ends within
// half a frame past the caps, the certificate passes, and the worst frame comes closer to its
// voxels than with the image closed by background (where the end frames are the worst).
#include "refine/time_caps.h"

#include <gtest/gtest.h>

#include <cmath>

#include "delaunay/predicates.h"
#include "domain/surface_oracle.h"
#include "mesh/mesh_check.h"
#include "mesh/mesh_slice.h"
#include "refine/fidelity_certificate.h"
#include "refine/refine_checks.h"

namespace mesh4d::refine {
namespace {

// The largest |error| of a label's section at a frame against the frame's voxels, over the
// labels and frames, as the certificate measures it.
double worst_frame_error(const mesh::Mesh4& m, const domain::LabelImage4& image) {
  double worst = 0;
  for (const LabelFidelity& l : certify(m, image).labels)
    worst = std::max(worst, std::abs(l.worst_frame_error));
  return worst;
}

TEST(TimeCaps, TheMeshEndsAtTheCapsWithFaithfulEndFrames) {
  const domain::LabelImage4 image = small_ventricle();
  RefineParams params;
  params.delta = 8;
  std::vector<std::string> warnings;
  const RefineResult r = refine_with_time_caps(image, params, nullptr, &warnings);
  // The caps lie half a frame past the end frames. The mesh reaches a little past them where
  // facets of the cap meet the ghosts' side of the ridge: half a frame further, under 2 % of
  // the end frame's volume is left, and a frame further next to nothing.
  const double caps[2] = {image.voxel_center(0, 0, 0, 0)[3] - 4,
                          image.voxel_center(0, 0, 0, 7)[3] + 4};
  for (mesh::Label l : r.mesh.labels) ASSERT_TRUE(l == 1 || l == 2) << l;
  const auto volume = [&](double t) {
    double v = 0;
    for (const auto& [label, x] : mesh::slice_volumes(r.mesh, t)) v += x;
    return v;
  };
  const double end_frames[2] = {volume(caps[0] + 4), volume(caps[1] - 4)};
  EXPECT_LT(volume(caps[0] - 4), 0.02 * end_frames[0]);
  EXPECT_LT(volume(caps[1] + 4), 0.02 * end_frames[1]);
  EXPECT_LT(volume(caps[0] - 8), 1e-4 * end_frames[0]);
  EXPECT_LT(volume(caps[1] + 8), 1e-4 * end_frames[1]);
  // The pentatopes whose centroid lay past a cap went to the ghosts where that kept the
  // topology, and the vertices past a cap moved onto it where that keeps every pentatope's
  // quality: a tenth of a frame past the caps the mesh keeps about a twentieth of the end
  // frames' volume (a tenth with the moves alone, a fifth without either).
  std::printf(
      "past the caps by a tenth of a frame: %.3f, %.3f of the end frames; %zu pentatopes to "
      "the ghosts; %zu of %zu vertices past them flattened, one left %.2f past\n",
      volume(caps[0] - 0.8) / end_frames[0], volume(caps[1] + 0.8) / end_frames[1],
      r.caps.relabeled, r.caps.flattened, r.caps.past, r.caps.farthest_left);
  EXPECT_GT(r.caps.relabeled, 0u);
  EXPECT_GT(r.caps.flattened, r.caps.past / 3);
  EXPECT_LT(volume(caps[0] - 0.8), 0.08 * end_frames[0]);
  EXPECT_LT(volume(caps[1] + 0.8), 0.08 * end_frames[1]);
  double earliest = caps[1], latest = caps[0];
  for (const Point4& v : r.mesh.vertices)
    earliest = std::min(earliest, v[3]), latest = std::max(latest, v[3]);
  EXPECT_LE(caps[0] - earliest, r.caps.farthest_left) << "no vertex farther past than reported";
  EXPECT_LE(latest - caps[1], r.caps.farthest_left);
  for (const auto& c : r.mesh.pentatopes) {
    const auto& x = r.mesh.vertices;
    ASSERT_GT(delaunay::orient4(x[c[0]], x[c[1]], x[c[2]], x[c[3]], x[c[4]]), 0)
        << "every pentatope keeps its orientation (exactly)";
  }
  const mesh::BoundaryCheck check = mesh::check_boundary(r.mesh);
  EXPECT_EQ(check.non_feature_uses, 0u);
  EXPECT_EQ(check.odd, 0u);
  const FidelityCertificate certificate = certify(r.mesh, image);
  EXPECT_TRUE(certificate.defects().empty()) << ::testing::PrintToString(certificate.defects());

  // The same image closed with background half a frame past its ends.
  domain::LabelImage4 closed = image;
  domain::validate_and_close(closed);
  const domain::SurfaceOracle oracle(closed);
  const RefineResult without = refine(oracle, params);
  const double capped = worst_frame_error(r.mesh, image);
  const double rounded = worst_frame_error(without.mesh, image);
  std::printf("worst frame volume error: %.3f with the caps, %.3f closed by background\n", capped,
              rounded);
  EXPECT_LT(capped, 0.7 * rounded) << "without the caps the end frames are the worst";
}

}  // namespace
}  // namespace mesh4d::refine
