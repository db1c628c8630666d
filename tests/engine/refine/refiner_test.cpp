// Sequential refinement with the rules implemented so far (R1 to R4, sizing): termination,
// validity, the radius-edge and sliver bounds on the output, labels, volume, cancellation and the
// budget.
#include "refine/refiner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "delaunay/checker.h"
#include "domain/image_io.h"
#include "domain/periodic_time.h"
#include "domain/phantoms.h"
#include "domain/segmentation_cleanup.h"
#include "mesh/topology_certificate.h"
#include "refine/fidelity_certificate.h"
#include "refine/refine_checks.h"
#include "refine/time_caps.h"

namespace mesh4d::refine {
namespace {

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
  std::size_t on_surface = 0, total = 0;
  for (const auto& b : r.mesh.boundary)
    for (auto v : b.vertices)
      on_surface += r.mesh.vertex_kinds[v] == mesh::VertexKind::feature, ++total;
  std::printf(
      "insertions R1..R5: %llu %llu %llu %llu %llu, removals %llu; boundary vertices on "
      "the surface: %zu of %zu\n",
      (unsigned long long)r.stats.insertions[0], (unsigned long long)r.stats.insertions[1],
      (unsigned long long)r.stats.insertions[2], (unsigned long long)r.stats.insertions[3],
      (unsigned long long)r.stats.insertions[4], (unsigned long long)r.stats.removals[4],
      on_surface, total);
  expect_fidelity(r.mesh, oracle, {0, 1}, kDistanceBound * params.delta, r.sag.largest_offset);
}

// One thread and one seed give one mesh, also for the second job of a process: state kept
// between runs (the vertex removal's per-thread triangulation once carried its walk on) must
// not leak into the next.
TEST(Refiner, SameSeedGivesTheSameMeshRunAfterRun) {
  const auto image = domain::hypersphere_phantom({24, 24, 24, 24}, {1, 1, 1, 1}, 9);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 2.5;
  std::vector<mesh::Mesh4> meshes;
  for (int run = 0; run < 3; ++run) meshes.push_back(Refiner(oracle, params).run().mesh);
  ASSERT_GT(meshes[0].pentatopes.size(), 100u);
  for (int run = 1; run < 3; ++run) {
    EXPECT_EQ(meshes[run].vertices, meshes[0].vertices) << "run " << run;
    EXPECT_EQ(meshes[run].pentatopes, meshes[0].pentatopes) << "run " << run;
  }
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
  // Where pool, wall and background meet at the padded time caps the surface has sharp
  // corners that a boundary of size-δ facets cuts across: over seeds 1–14 the largest distance
  // was 0.42–0.57 δ (means 0.08 δ), over 140 parallel runs 0.40–0.57 δ and once 0.645 δ. Since
  // the pinch repair starts at Δ/2 the tail is longer: over 28 parallel runs median
  // 0.50 δ, largest 0.70 δ, and once in CI 0.76 δ; hence 1.0 δ here. (The rules bound it only
  // loosely: a boundary tetrahedron lies in its surface ball, centered on ∂Ω and no larger than
  // the circumball of one of its two pentatopes, which meets ∂Ω and so is kept below 2Δ by R2.)
  expect_fidelity(r.mesh, oracle, {0, 1, 2}, 1.0 * params.delta, r.sag.largest_offset);
  std::size_t components = 0;
  EXPECT_EQ(unmeshed_components(image, r.mesh, &components), 0u);
  EXPECT_EQ(components, 2u);
}

// Refines with the repair's counts from facet changes checked against full scans (the refiner
// throws on a difference), with one thread and with two (whose logs are applied one worker
// after the other); the image must need several rounds, so that some counts are compared.
void expect_pinch_counts_from_facet_changes_checked(const domain::SurfaceOracle& oracle,
                                                    RefineParams params) {
  for (unsigned threads : {1u, 2u}) {
    params.threads = threads;
    Refiner refiner(oracle, params);
    refiner.set_pinch_count_check(true);
    RefineResult r;
    ASSERT_NO_THROW(r = refiner.run()) << threads << " threads";
    EXPECT_GT(r.stats.pentatopes, 0u);
    std::printf("%u threads: %zu counts from facet changes compared with full scans\n", threads,
                refiner.pinch_counts_checked());
    EXPECT_GT(refiner.pinch_counts_checked(), 0u) << threads << " threads: nothing was compared";
  }
}

// The repair's rounds count pinches from the facet changes of their operations.
TEST(Refiner, PinchCountsFromFacetChangesMatchFullCounts) {
  auto image = domain::beating_ventricle_phantom({50, 50, 22, 8}, {3.54, 3.54, 12, 2});
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 6;
  expect_pinch_counts_from_facet_changes_checked(oracle, params);
}

// In periodic time both counts take the triangles the covering counts only (lowest vertex in
// the middle sheet): the ventricle's cycle in a 3-sheeted covering.
TEST(Refiner, PinchCountsFromFacetChangesMatchFullCountsOfTheMiddleSheet) {
  domain::LabelImage4 cycle =
      domain::beating_ventricle_phantom({50, 50, 22, 12}, {3.54, 3.54, 12, 1});
  cycle.set_time_spacing(8);
  const domain::TimePeriod period = domain::cycle_period(cycle);
  domain::LabelImage4 covering = domain::tile_cycle(cycle, 12);
  domain::validate_and_close(covering);
  const domain::SurfaceOracle oracle(covering);
  RefineParams params;
  params.delta = 6;
  params.period_start = period.start;
  params.period = period.length;
  expect_pinch_counts_from_facet_changes_checked(oracle, params);
}

// When the progress reports were sent: the forced one after the rules' first pass comes before
// the repair starts, and the one of the extraction after the repair and the relabeling end.
class ReportTimes final : public ProgressSink {
 public:
  void on_progress(const Progress& p) override {
    if (first < 0) first = p.elapsed_seconds;
    if (p.phase == Phase::extracting) extracting = p.elapsed_seconds;
  }
  double first = -1, extracting = -1;
};

// The manifold stage (manifold_relabeling.h) on the ventricle at δ = 5, where the rules, the
// pinch repair and the pinch relabeling leave some 300 (vertex, label) pairs whose link in the
// region's boundary is not a 2-sphere: the stage leaves a handful, the count it reports is the
// one the certificate finds on the output, and the warning names it. The repair and the stage
// run between the rules' first pass and the extraction.
TEST(Refiner, ManifoldStageLeavesFewFailingLinksAndReportsThem) {
  auto image = domain::beating_ventricle_phantom();
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 5;
  Refiner refiner(oracle, params);
  ReportTimes reports;
  const RefineResult r = refiner.run(&reports);
  std::size_t certified = 0;
  for (const auto& l : mesh::certify_topology(r.mesh).labels) certified += l.non_manifold_vertices;
  std::printf("ventricle δ=5: %zu relabeled, %zu failing links left, certificate %zu\n",
              r.relabeled, r.non_manifold_left, certified);
  EXPECT_EQ(r.non_manifold_left, certified);
  EXPECT_LE(r.non_manifold_left, 10u);
  expect_only_manifold_warning(r);
  EXPECT_GT(r.repair_seconds, 0);
  ASSERT_GE(reports.first, 0);
  ASSERT_GE(reports.extracting, reports.first);
  EXPECT_LE(r.repair_seconds, reports.extracting - reports.first);
}

// A real heart (../shared/data/heart4d, skipped where absent): cavity, myocardium and background
// meet at the valve plane and at the time caps, where the rules alone leave pinched regions
// and the repair and the relabeling must close them; at δ = 10 to stay fast.
TEST(Refiner, PatientClosesEveryPinchWhereThreeLabelsMeet) {
  const std::filesystem::path file =
      std::filesystem::path(MESH4D_HEART_DATA_DIR) / "Pat01_mse4d_label4d.nii.gz";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "no real data: " << file << " is absent";
  auto image = domain::read_label_image(file.string());
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 10;
  Refiner refiner(oracle, params);
  const RefineResult r = refiner.run();
  std::printf("Pat01 δ=10: %llu pentatopes, %zu relabeled, max ρ %.2f, min τ %.4f, %.1f s\n",
              (unsigned long long)r.stats.pentatopes, r.relabeled, r.stats.radius_edge_ratio.max,
              r.stats.normalized_volume.min, r.stats.elapsed_seconds);
  const auto check = delaunay::check_triangulation(refiner.triangulation());
  ASSERT_TRUE(check.ok) << check.error;
  EXPECT_LE(r.stats.radius_edge_ratio.max, params.radius_edge_bound);
  EXPECT_GE(r.stats.normalized_volume.min, params.sliver_bound);
  expect_only_manifold_warning(r);
  // At this coarse δ one boundary tetrahedron lies 0.511 δ from ∂Ω, with or without the
  // manifold stage (a sample of every tetrahedron; the 2,000 sampled before missed it).
  expect_fidelity(r.mesh, oracle, {0, 1, 2}, 0.55 * params.delta, r.sag.largest_offset);
}

// Pat01 at the paper's spacing (first 15 frames, cleaned at the default, as bench/refine_bench):
// the refinement cut off a blood-pool piece of three pentatopes, which the image joins to the
// rest; the piece matching gives it its neighbors' label, so each label is as many pieces as
// the cleaned image has, none touching another (without the step: 2 blood-pool pieces). About
// 8 s.
TEST(Refiner, PatientRegionsAreTheCleanedImagesPieces) {
  auto image = patient_at_papers_spacing("Pat01");
  if (!image) GTEST_SKIP() << "no real data in " << MESH4D_HEART_DATA_DIR;
  domain::clean_segmentation(*image, domain::kDefaultMinIslandVoxels);
  const domain::SurfaceOracle oracle(*image);
  RefineParams params;
  params.delta = 5;
  const RefineResult r = refine(oracle, params);
  const FidelityCertificate c = certify(r.mesh, *image);
  std::size_t failing = 0;
  for (const LabelFidelity& l : c.labels) failing += l.non_manifold_vertices;
  EXPECT_EQ(r.non_manifold_left, failing) << "the count the job reports is the output's";
  for (const LabelFidelity& l : c.labels) {
    std::printf(
        "Pat01 paper spacing label %u: mesh %zu pieces (%zu touching), image %zu; "
        "non-manifold vertices %zu\n",
        unsigned{l.label}, l.mesh_pieces, l.touching_pieces, l.image_pieces,
        l.non_manifold_vertices);
    EXPECT_EQ(l.mesh_pieces, l.image_pieces) << "label " << l.label;
    EXPECT_EQ(l.touching_pieces, 0u) << "label " << l.label;
  }
  expect_only_manifold_warning(r);
}

// Pat05 at the paper's spacing (1.77, 1.77, 6, 1; first 15 frames, as bench/refine_bench),
// seed 5: the repair left a pinch whose only allowed join was filling the second of two equally
// long gaps (the first, myocardium with free vertices, may not move), and the free-vertex
// removal and rules after it brought the same pinch back; 2 pinched triangles stayed until every
// gap could be the one kept (link_labels.h). About 6 s.
TEST(Refiner, RelabelingCanKeepEitherOfTwoEqualGaps) {
  auto image = patient_at_papers_spacing("Pat05");
  if (!image) GTEST_SKIP() << "no real data in " << MESH4D_HEART_DATA_DIR;
  const domain::SurfaceOracle oracle(*image);
  RefineParams params;
  params.delta = 5;
  params.seed = 5;
  Refiner refiner(oracle, params);
  const RefineResult r = refiner.run();
  std::printf("Pat05 paper spacing, seed 5: %llu pentatopes, %zu relabeled, %.1f s\n",
              (unsigned long long)r.stats.pentatopes, r.relabeled, r.stats.elapsed_seconds);
  expect_only_manifold_warning(r);
  EXPECT_GT(r.relabeled, 0u);
  // One boundary tetrahedron lies 0.574 δ from ∂Ω, with or without the manifold step (it comes
  // from the rules and the relabeling): every tetrahedron measured.
  expect_fidelity(r.mesh, oracle, {0, 1, 2}, 0.6 * params.delta, r.sag.largest_offset);
}

// Pat02 (seed 3) and Pat05 (seed 1) at the paper's spacing, prepared as bench/refine_bench's
// rows (cleaned, time caps): the manifold sampling's rounds ended with a link failing, two ways.
// On Pat02 every restricted facet of the last failing vertex had the same label function at
// both circumcenters (a relabeling had moved one side), so no facet gave a sample: ∂Ω's point
// nearest each Voronoi edge's middle is sampled then. On Pat05 every sample lay within Δ/4 of a
// feature vertex: the spacing halves then. Each alone leaves the other's link. About 30 s.
TEST(Refiner, ManifoldSamplingLeavesNoLinkFailingAtThePapersSpacing) {
  const std::pair<const char*, std::uint64_t> cases[] = {{"Pat02", 3}, {"Pat05", 1}};
  for (const auto& [name, seed] : cases) {
    SCOPED_TRACE(std::string(name) + ", seed " + std::to_string(seed));
    auto image = patient_at_papers_spacing(name, false);
    if (!image) GTEST_SKIP() << "no real data in " << MESH4D_HEART_DATA_DIR;
    domain::clean_segmentation(*image, domain::kDefaultMinIslandVoxels);
    RefineParams params;
    params.delta = 5;
    params.seed = seed;
    std::vector<std::string> warnings;
    const RefineResult r = refine_with_time_caps(*image, params, nullptr, &warnings);
    const FidelityCertificate c = certify(r.mesh, *image);
    std::printf("%s paper spacing, seed %llu: %zu sampling points in %d rounds, %zu links left\n",
                name, (unsigned long long)seed, r.manifold_points, r.manifold_rounds,
                r.non_manifold_left);
    EXPECT_EQ(r.non_manifold_left, 0u);
    for (const LabelFidelity& l : c.labels) {
      SCOPED_TRACE("label " + std::to_string(l.label));
      EXPECT_EQ(l.non_manifold_vertices, 0u);
      EXPECT_EQ(l.non_manifold_edges, 0u);
      EXPECT_EQ(l.non_manifold_triangles, 0u);
      EXPECT_EQ(l.mesh_pieces, l.image_pieces);
    }
  }
}

// The other single-label phantoms: a hyper-torus (a hole), two blobs that merge and split over
// time (closed in time by padding; where they first touch, ∂Ω has a saddle whose local feature
// size goes to 0, below any uniform Δ: the pinch repair samples it), and the same blobs' first
// frames only, before they touch: two components, each of which must be meshed.
TEST(Refiner, TorusAndBlobsKeepFidelity) {
  struct Case {
    const char* name;
    domain::LabelImage4 image;
    double delta;
    std::size_t components;
    double distance_bound;  // × δ
  };
  const auto blobs = domain::merging_blobs_phantom();
  const auto& d = blobs.dims();
  // Three frames, stretched in time (4 units per frame) to keep the slab thicker than Δ.
  domain::LabelImage4 apart({d[0], d[1], d[2], 3},
                            {blobs.spacing()[0], blobs.spacing()[1], blobs.spacing()[2], 4});
  for (std::size_t i = 0; i < apart.voxel_count(); ++i) apart.set(i, blobs.at(i));
  // Where the blobs first touch, a boundary tetrahedron can span the saddle (local feature size
  // 0): over seeds 1–6 the largest distance was 0.38–0.75 δ (means 0.09 δ), hence 0.8 δ for
  // that case alone.
  Case cases[] = {{"hypertorus", domain::hypertorus_phantom(), 2.5, 1, kDistanceBound},
                  {"blobs", blobs, 2.5, 1, 0.8},
                  {"blobs before they merge", apart, 2.5, 2, kDistanceBound}};
  for (auto& c : cases) {
    domain::validate_and_close(c.image);
    const domain::SurfaceOracle oracle(c.image);
    RefineParams params;
    params.delta = c.delta;
    Refiner refiner(oracle, params);
    const RefineResult r = refiner.run();
    SCOPED_TRACE(c.name);
    EXPECT_TRUE(delaunay::check_triangulation(refiner.triangulation()).ok);
    EXPECT_LT(r.stats.radius_edge_ratio.max, params.radius_edge_bound);
    EXPECT_GE(r.stats.normalized_volume.min, params.sliver_bound);
    const double meshed = output_volume(r.mesh), voxels = voxel_volume(c.image, 1);
    std::printf("%s δ=%.1f: %llu pentatopes, volume %.0f vs voxels %.0f, %.2f s\n", c.name, c.delta,
                (unsigned long long)r.stats.pentatopes, meshed, voxels, r.stats.elapsed_seconds);
    EXPECT_NEAR(meshed / voxels, 1.0, 0.15);
    expect_fidelity(r.mesh, oracle, {0, 1}, c.distance_bound * params.delta, r.sag.largest_offset);
    std::size_t components = 0;
    EXPECT_EQ(unmeshed_components(c.image, r.mesh, &components), 0u);
    EXPECT_EQ(components, c.components);
  }
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

TEST(Refiner, CancellationAndBudgetStopCleanly) {
  expect_cancellation_and_budget_stop(1);
}

}  // namespace
}  // namespace mesh4d::refine
