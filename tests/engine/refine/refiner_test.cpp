// Sequential refinement with the rules implemented so far (R1 to R4, sizing): termination,
// validity, the radius-edge and sliver bounds on the output, labels, volume, cancellation and the
// budget.
#include "refine/refiner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "delaunay/checker.h"
#include "delaunay/geometry.h"
#include "domain/phantoms.h"

namespace mesh4d::refine {
namespace {

double output_volume(const mesh::Mesh4& m, mesh::Label label = 0) {
  double v = 0;
  for (std::size_t i = 0; i < m.pentatopes.size(); ++i) {
    if (label && m.labels[i] != label) continue;
    delaunay::Simplex4 s;
    for (int k = 0; k < 5; ++k) s[k] = m.vertices[m.pentatopes[i][k]];
    v += std::abs(delaunay::signed_volume(s));
  }
  return v;
}

double voxel_volume(const domain::LabelImage4& image, domain::Label label) {
  double n = 0;
  for (std::size_t i = 0; i < image.voxel_count(); ++i) n += image.at(i) == label;
  const auto& s = image.spacing();
  return n * s[0] * s[1] * s[2] * s[3];
}

TEST(RefineParams, OutOfRangeValuesAreRefusedByName) {
  auto error_of = [](RefineParams p) {
    try {
      validate(p);
    } catch (const ParamError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  RefineParams p;
  EXPECT_EQ(error_of(p), "no error");
  p.delta = NAN;
  EXPECT_NE(error_of(p).find("delta"), std::string::npos);
  p = {};
  p.radius_edge_bound = 0.5;
  EXPECT_NE(error_of(p).find("radius_edge_bound"), std::string::npos);
  p = {};
  p.picking_ratio = 1.5;
  EXPECT_NE(error_of(p).find("picking_ratio"), std::string::npos);
  p = {};
  p.vertex_budget = 3;
  EXPECT_NE(error_of(p).find("vertex_budget"), std::string::npos);
}

TEST(Refiner, HypersphereTerminatesValidWithBoundedRatioAndTheRightVolume) {
  const auto image = domain::hypersphere_phantom({32, 32, 32, 32}, {1, 1, 1, 1}, 12);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 3;
  Refiner refiner(oracle, params);
  const RefineResult r = refiner.run();
  const auto check = delaunay::check_triangulation(refiner.triangulation());
  ASSERT_TRUE(check.ok) << check.error;
  ASSERT_GT(r.stats.pentatopes, 100u);
  EXPECT_LT(r.stats.radius_edge_ratio.max, params.radius_edge_bound);
  EXPECT_GE(r.stats.normalized_volume.min, params.sliver_bound);  // R4 leaves no interior sliver
  for (auto l : r.mesh.labels) ASSERT_EQ(l, 1);
  const double ball = std::numbers::pi * std::numbers::pi / 2 * std::pow(12.0, 4);
  const double meshed = output_volume(r.mesh);
  std::printf(
      "hypersphere δ=3: %llu vertices, %llu pentatopes, %llu boundary tets, volume %.0f "
      "vs ball %.0f, max ρ %.2f, min τ %.4f, %.2f s\n",
      (unsigned long long)r.stats.vertices, (unsigned long long)r.stats.pentatopes,
      (unsigned long long)r.stats.boundary_tetrahedra, meshed, ball, r.stats.radius_edge_ratio.max,
      r.stats.normalized_volume.min, r.stats.elapsed_seconds);
  EXPECT_NEAR(meshed / ball, 1.0, 0.1);
}

TEST(Refiner, VentricleGetsBothLabels) {
  auto image = domain::beating_ventricle_phantom({50, 50, 22, 8}, {3.54, 3.54, 12, 2});
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 8;
  Refiner refiner(oracle, params);
  const RefineResult r = refiner.run();
  EXPECT_TRUE(delaunay::check_triangulation(refiner.triangulation()).ok);
  const double pool = output_volume(r.mesh, 1), wall = output_volume(r.mesh, 2);
  std::printf(
      "ventricle δ=8: %llu pentatopes; blood pool %.0f vs voxels %.0f; myocardium %.0f "
      "vs voxels %.0f\n",
      (unsigned long long)r.stats.pentatopes, pool, voxel_volume(image, 1), wall,
      voxel_volume(image, 2));
  EXPECT_GT(pool, 0);
  EXPECT_GT(wall, 0);
}

TEST(Refiner, HalvingDeltaAddsVertices) {
  const auto image = domain::hypersphere_phantom({28, 28, 28, 28}, {1, 1, 1, 1}, 10);
  const domain::SurfaceOracle oracle(image);
  RefineParams coarse, fine;
  coarse.delta = 6;
  fine.delta = 3;
  const auto a = Refiner(oracle, coarse).run();
  const auto b = Refiner(oracle, fine).run();
  EXPECT_GT(b.stats.vertices, 2 * a.stats.vertices);
}

class StopAfter : public ProgressSink {
 public:
  void on_progress(const Progress& p) override { last = p; }
  bool should_abort() override { return ++polls > 2; }
  Progress last;
  int polls = 0;
};

TEST(Refiner, CancellationAndBudgetStopCleanly) {
  const auto image = domain::hypersphere_phantom({32, 32, 32, 32}, {1, 1, 1, 1}, 12);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 2;
  StopAfter sink;
  EXPECT_THROW(Refiner(oracle, params).run(&sink), Cancelled);
  params.vertex_budget = 200;
  EXPECT_THROW(Refiner(oracle, params).run(), BudgetExceeded);
}

}  // namespace
}  // namespace mesh4d::refine
