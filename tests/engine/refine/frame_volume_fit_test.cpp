// The frames' volumes fitted after the sag offset, in open time (the caps) and in periodic time,
// measured here by slicing the output against the voxels, not by the fit's own count. On a
// phantom made to provoke the shortfall that the offset alone leaves (a tube beating between
// 2.2 and 2.7 Δ across inside a sleeve, thinner than Pat03's systolic cavity is in voxels and
// faster), the fit takes most of it back; the quality guard holds the rest, and holds: nothing
// but boundary vertices moves, in space only, within half a voxel, with no pentatope turned, no
// new sliver and no radius-edge ratio past the bound.
#include "refine/frame_volume_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "domain/time_scale.h"
#include "mesh/mesh_slice.h"
#include "refine/fidelity_certificate.h"
#include "refine/periodic_time.h"
#include "refine/refine_checks.h"
#include "refine/refiner.h"
#include "refine/time_caps.h"

namespace mesh4d::refine {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A tube along z (label 1) in a sleeve (label 2), its radius beating once over the 12 frames:
// frame 12 would be frame 0 again.
domain::LabelImage4 beating_tube() {
  const domain::Dims4 d{36, 36, 16, 12};
  domain::LabelImage4 image(d, {1, 1, 1, 1});
  for (std::size_t t = 0; t < d[3]; ++t) {
    const double s = std::sin(kPi * static_cast<double>(t) / static_cast<double>(d[3]));
    const double tube = 6.5 + 1.5 * (1 - s * s), sleeve = tube + 6.0;
    for (std::size_t z = 2; z + 2 < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x) {
          const double r = std::hypot(x - 17.5, y - 17.7);
          if (r < sleeve) image.set(x, y, z, t, r < tube ? 1 : 2);
        }
  }
  return image;
}

// Each label's section at each frame against its voxels: the relative errors.
std::vector<double> section_errors(const mesh::Mesh4& m, const domain::LabelImage4& image) {
  const auto& d = image.dims();
  std::vector<double> errors;
  for (std::size_t t = 0; t < d[3]; ++t) {
    double voxels[3] = {0, 0, 0};
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x) voxels[image.at(x, y, z, t)] += 1;
    const auto sections = mesh::slice_volumes(m, image.voxel_center(0, 0, 0, t)[3]);
    for (mesh::Label l : {1, 2}) {
      const double v = sections.count(l) ? sections.at(l) : 0;
      errors.push_back(v / voxels[l] - 1);
    }
  }
  return errors;
}

double worst_of(const std::vector<double>& errors) {
  double worst = 0;
  for (double e : errors) worst = std::max(worst, std::abs(e));
  return worst;
}

double mean_of(const std::vector<double>& errors) {
  double sum = 0;
  for (double e : errors) sum += std::abs(e);
  return sum / static_cast<double>(errors.size());
}

RefineParams params_with(bool fit) {
  RefineParams params;
  params.delta = 3;
  params.fit_frame_volumes = fit;
  return params;
}

void expect_fitted(bool periodic) {
  // At the time scale a job chooses (domain/time_scale.h), so that the frames are sampled.
  domain::LabelImage4 image = beating_tube();
  image.set_time_spacing(domain::automatic_time_scale(image, params_with(true).delta, periodic));
  std::vector<std::string> warnings;
  const auto run = [&](bool fit) {
    return periodic ? refine_periodic(image, params_with(fit), nullptr, &warnings)
                    : refine_with_time_caps(image, params_with(fit), nullptr, &warnings);
  };
  const RefineResult on = run(true), off = run(false);
  const std::vector<double> fitted = section_errors(on.mesh, image),
                            offset = section_errors(off.mesh, image);
  const double with = worst_of(fitted), without = worst_of(offset);
  const FrameVolumeFit& fit = on.sag.fit;
  std::printf(
      "%s: worst frame %.4f with the offset alone, %.4f fitted; mean |error| %.4f and %.4f (the "
      "fit's own count %.4f → %.4f in %zu rounds over %zu sections, largest move %.3f)\n",
      periodic ? "periodic" : "open", without, with, mean_of(offset), mean_of(fitted),
      fit.worst_before, fit.worst_after, fit.rounds, fit.sections, fit.largest_move);
  // The phantom provokes the shortfall, and the fit takes most of it back (on the patients and
  // the ventricle phantom at δ 5, all of it to within 1.1 %: docs/performance.md). Not all of
  // it in every section: on this phantom at δ 3 one section keeps 3–6 % on half of seeds 1–6,
  // in either time.
  EXPECT_GT(without, 0.05);
  EXPECT_LT(mean_of(fitted), 0.4 * mean_of(offset));
  EXPECT_LT(with, without);
  EXPECT_GT(fit.rounds, 0u);
  // The fit's own count is an outsider's: the sections at the frames against the voxels. In
  // open time it also counts the caps' ghost frames (dropped after it), so its worst is at
  // least the image frames' worst.
  if (periodic)
    EXPECT_NEAR(std::abs(fit.worst_after), with, 0.005);
  else
    EXPECT_GT(std::abs(fit.worst_after), with - 0.005);
  // Only the vertices' places differ, by at most half a voxel, in space.
  ASSERT_EQ(on.mesh.vertices.size(), off.mesh.vertices.size());
  EXPECT_EQ(on.mesh.pentatopes, off.mesh.pentatopes);
  EXPECT_EQ(on.mesh.labels, off.mesh.labels);
  double farthest = 0;
  const double first = image.voxel_center(0, 0, 0, 0)[3];
  const double last = image.voxel_center(0, 0, 0, image.dims()[3] - 1)[3];
  for (std::size_t v = 0; v < on.mesh.vertices.size(); ++v) {
    const auto& a = on.mesh.vertices[v];
    const auto& b = off.mesh.vertices[v];
    // In time only the caps' flattening moves vertices, past the end frames.
    if (periodic || (b[3] > first && b[3] < last)) {
      EXPECT_EQ(a[3], b[3]) << "vertex " << v;
    }
    farthest = std::max(farthest, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
  }
  EXPECT_GT(farthest, 0);
  EXPECT_LE(farthest, 0.5 + 1e-9);
  expect_moves_kept_quality(on, off, params_with(true));
  if (!periodic) {
    const FidelityCertificate certificate = certify(on.mesh, image);
    EXPECT_TRUE(certificate.defects().empty()) << ::testing::PrintToString(certificate.defects());
  }
}

TEST(FrameVolumeFit, ABeatingTubeGetsMostOfItsShortfallBackInOpenTime) {
  expect_fitted(false);
}

TEST(FrameVolumeFit, ABeatingTubeGetsMostOfItsShortfallBackInPeriodicTime) {
  expect_fitted(true);
}

}  // namespace
}  // namespace mesh4d::refine
