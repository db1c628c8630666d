// Periodic time: the covering is a valid Delaunay triangulation that is the same in each sheet,
// the mesh is glued at the seam (every facet there matched), the certificate passes on the
// glued cycle, and the first and last frames are meshed like the others. On a truly periodic
// phantom (the beating ventricle) and on a ball that lives across the end of the cycle.
#include "refine/periodic_time.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "delaunay/checker.h"
#include "delaunay/geometry.h"
#include "domain/image_io.h"
#include "domain/periodic_time.h"
#include "domain/phantoms.h"
#include "domain/segmentation_cleanup.h"
#include "domain/surface_oracle.h"
#include "domain/time_scale.h"
#include "mesh/mesh_check.h"
#include "mesh/mesh_slice.h"
#include "mesh/periodic_mesh.h"
#include "refine/fidelity_certificate.h"

namespace mesh4d::refine {
namespace {

using Facet = std::array<std::uint32_t, 4>;

Facet sorted_facet(const std::array<std::uint32_t, 5>& p, int skip,
                   const std::vector<std::uint32_t>& id) {
  Facet f;
  for (int k = 0, m = 0; k < 5; ++k)
    if (k != skip) f[m++] = id[p[k]];
  std::sort(f.begin(), f.end());
  return f;
}

// The seam: twins exactly a period apart, every facet of the glued cycle in one or two
// pentatopes, and those in one exactly the boundary tetrahedra against the outside. Returns how
// many facets use a vertex past the period (the seam's).
std::size_t expect_glued_at_the_seam(const mesh::Mesh4& m) {
  EXPECT_TRUE(m.periodic());
  for (const auto& [later, earlier] : m.periodic_twins) {
    Point4 p = m.vertices[earlier];
    p[3] += m.period;
    EXPECT_EQ(m.vertices[later], p);
    EXPECT_GE(m.vertices[later][3], m.period_start + m.period);
  }
  const std::vector<std::uint32_t> id = mesh::glued_vertex_ids(m);
  std::map<Facet, int> uses;
  std::size_t seam = 0;
  for (const auto& p : m.pentatopes)
    for (int s = 0; s < 5; ++s) ++uses[sorted_facet(p, s, id)];
  for (const auto& p : m.pentatopes)
    for (int s = 0; s < 5; ++s) {
      bool past = false;
      for (int k = 0; k < 5; ++k) past = past || (k != s && id[p[k]] != p[k]);
      seam += past;
    }
  std::set<Facet> outside;
  for (const auto& b : m.boundary)
    if (b.outer == 0) {
      Facet f;
      for (int k = 0; k < 4; ++k) f[k] = id[b.vertices[k]];
      std::sort(f.begin(), f.end());
      outside.insert(f);
    }
  std::size_t once = 0;
  for (const auto& [f, n] : uses) {
    EXPECT_LE(n, 2);
    if (n == 1) {
      ++once;
      EXPECT_TRUE(outside.count(f)) << "an unmatched facet that is not on the boundary";
    }
  }
  EXPECT_EQ(once, outside.size());
  return seam;
}

// Each frame's section against its voxels, per label: {worst of the first and last frames,
// worst of the others}.
std::pair<double, double> frame_errors(const mesh::Mesh4& m, const domain::LabelImage4& image) {
  const auto& d = image.dims();
  const auto& s = image.spacing();
  std::pair<double, double> worst{0, 0};
  for (std::size_t f = 0; f < d[3]; ++f) {
    std::map<mesh::Label, double> voxels;
    for (std::size_t i = 0; i < d[0] * d[1] * d[2]; ++i)
      if (const auto l = image.at(i + f * d[0] * d[1] * d[2])) voxels[l] += s[0] * s[1] * s[2];
    const auto section = mesh::slice_volumes(m, image.voxel_center(0, 0, 0, f)[3]);
    for (const auto& [l, v] : voxels) {
      const auto it = section.find(l);
      const double e = std::abs((it == section.end() ? 0 : it->second) / v - 1);
      double& w = (f == 0 || f + 1 == d[3]) ? worst.first : worst.second;
      w = std::max(w, e);
    }
  }
  return worst;
}

// The ventricle over 12 frames in a covering that reaches `margin_frames` past each end of the
// period (12: the cycle tiled three times), with a trusted band of `trusted_frames` (0: half the
// margin), refined on `threads` threads.
void expect_periodic_delaunay_glued_at_the_seam(std::size_t margin_frames,
                                                std::size_t trusted_frames = 0,
                                                unsigned threads = 1) {
  domain::LabelImage4 cycle =
      domain::beating_ventricle_phantom({50, 50, 22, 12}, {3.54, 3.54, 12, 1});
  cycle.set_time_spacing(8);
  const domain::TimePeriod period = domain::cycle_period(cycle);
  domain::LabelImage4 covering = domain::tile_cycle(cycle, margin_frames);
  ASSERT_EQ(covering.dims()[3], 12 + 2 * margin_frames);
  domain::validate_and_close(covering);
  const domain::SurfaceOracle oracle(covering);
  RefineParams params;
  params.delta = 8;
  params.period_start = period.start;
  params.period = period.length;
  const double margin = margin_frames < 12 ? 8.0 * double(margin_frames) : period.length;
  params.period_margin = margin_frames < 12 ? margin : 0;
  params.period_trusted = 8.0 * double(trusted_frames);
  params.threads = threads;
  const double trusted = trusted_frames > 0 ? params.period_trusted : margin / 2;
  Refiner refiner(oracle, params);
  // After every stage, every pentatope's translates carry its label (the run throws if not).
  refiner.set_translate_label_check(true);
  RefineResult r;
  ASSERT_NO_THROW(r = refiner.run());
  EXPECT_GT(refiner.translate_labels_checked(), 1000u);

  const auto& tri = refiner.triangulation();
  const delaunay::CheckResult valid = delaunay::check_triangulation(tri);
  ASSERT_TRUE(valid.ok) << valid.error;
  // The same in each sheet: every pentatope anchored in the middle sheet, small enough to be
  // one of the periodic triangulation's (circumradius under half the trusted band, which the
  // labeled ones are), has its translates one period below and above wherever their
  // circumballs lie within the covering (farther out the covering is cut off, and the box's
  // corners may lie in them).
  const auto& st = tri.store();
  std::map<Point4, mesh4d::VertexId> at;
  for (mesh4d::VertexId v = 1; v < st.vertex_slots(); ++v)
    if (st.vertex(v).kind != delaunay::VertexKind::removed) at[st.point(v)] = v;
  // The point set is invariant under a shift by T within the covering: every vertex whose
  // translate lies in it has a twin there (box corners aside).
  std::size_t twins_checked = 0, twins_missing = 0;
  for (const auto& [p, v] : at) {
    if (st.vertex(v).kind == delaunay::VertexKind::box) continue;
    for (double shift : {-period.length, period.length}) {
      Point4 q = p;
      q[3] += shift;
      if (q[3] < period.start - margin || q[3] >= period.start + period.length + margin) continue;
      ++twins_checked;
      twins_missing += !at.count(q);
    }
  }
  EXPECT_GT(twins_checked, 1000u);
  EXPECT_EQ(twins_missing, 0u) << "of " << twins_checked << " translates of vertices";
  // The symbolic tie-break between cospherical points orders them by id: any two vertices of
  // one sheet must be in the same order as their translates in the next, or the sheets may be
  // triangulated differently where points are cospherical (the ventricle has thousands of such
  // ties). (A vertex and its own translate are in one circumball only where it is as long as
  // the period: never at the end.)
  std::size_t orders_checked = 0, orders_differing = 0;
  for (int sheet : {-1, 0}) {
    std::vector<std::pair<mesh4d::VertexId, mesh4d::VertexId>> moved;  // (translate, vertex)
    for (const auto& [p, v] : at) {
      if (st.vertex(v).kind == delaunay::VertexKind::box ||
          std::floor((p[3] - period.start) / period.length) != sheet)
        continue;
      Point4 q = p;
      q[3] += period.length;
      if (const auto it = at.find(q); it != at.end()) moved.push_back({it->second, v});
    }
    std::sort(moved.begin(), moved.end());
    for (std::size_t k = 1; k < moved.size(); ++k, ++orders_checked)
      orders_differing += moved[k].second < moved[k - 1].second;
  }
  EXPECT_GT(orders_checked, 1000u);
  EXPECT_EQ(orders_differing, 0u) << "of " << orders_checked << " pairs of translates";
  std::set<std::array<mesh4d::VertexId, 5>> cells;
  for (delaunay::CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c) || st.is_infinite(c)) continue;
    std::array<mesh4d::VertexId, 5> v;
    std::copy(std::begin(st.cell(c).v), std::end(st.cell(c).v), v.begin());
    std::sort(v.begin(), v.end());
    cells.insert(v);
  }
  std::size_t checked = 0, missing = 0;
  for (const auto& cell : cells) {
    double lowest = INFINITY;
    bool box = false;
    delaunay::Simplex4 s;
    for (int k = 0; k < 5; ++k) {
      s[k] = st.point(cell[k]);
      lowest = std::min(lowest, s[k][3]);
      box = box || st.vertex(cell[k]).kind == delaunay::VertexKind::box;
    }
    if (box || lowest < period.start || lowest >= period.start + period.length) continue;
    const Point4 center = delaunay::circumcenter(s);
    const double radius = delaunay::circumradius(s, center);
    if (radius >= trusted / 2) continue;
    for (double shift : {-period.length, period.length}) {
      const double moved = center[3] + shift;
      if (moved - radius < period.start - margin ||
          moved + radius >= period.start + period.length + margin)
        continue;
      ++checked;
      std::array<mesh4d::VertexId, 5> twin;
      bool all = true;
      for (int k = 0; k < 5 && all; ++k) {
        Point4 p = s[k];
        p[3] += shift;
        const auto it = at.find(p);
        all = it != at.end();
        if (all) twin[k] = it->second;
      }
      std::sort(twin.begin(), twin.end());
      missing += !all || !cells.count(twin);
    }
  }
  EXPECT_GT(checked, 1000u);  // translates checked
  EXPECT_EQ(missing, 0u) << "of " << checked;

  EXPECT_GT(expect_glued_at_the_seam(r.mesh), 100u);
  const mesh::BoundaryCheck boundary = mesh::check_boundary(r.mesh);
  EXPECT_EQ(boundary.odd, 0u);
  EXPECT_EQ(boundary.non_feature_uses, 0u);
  const FidelityCertificate certificate = certify(r.mesh, cycle);
  // (The refiner's own count says whether it knew of a failing link it could not mend.)
  EXPECT_TRUE(certificate.defects().empty())
      << ::testing::PrintToString(certificate.defects()) << "; the refiner counted "
      << r.non_manifold_left << " failing links left";
  for (const LabelFidelity& l : certificate.labels) EXPECT_EQ(l.mesh_pieces, 1u) << l.label;
  // Every frame meshed alike: the end frames are no worse than the others.
  const auto [ends, middle] = frame_errors(r.mesh, cycle);
  std::printf("worst frame volume error: %.3f first and last frames, %.3f the others\n", ends,
              middle);
  EXPECT_LT(ends, middle + 0.03);
  EXPECT_LT(middle, 0.12);

  // The certificate sees the seam: unglued, the facets there are a boundary nobody listed.
  mesh::Mesh4 unglued = r.mesh;
  unglued.periodic_twins.clear();
  EXPECT_FALSE(certify(unglued, cycle).defects().empty());
}

TEST(PeriodicTime, TheCoveringIsPeriodicDelaunayAndTheCycleIsGluedAtTheSeam) {
  expect_periodic_delaunay_glued_at_the_seam(12);
}

TEST(PeriodicTime, ANarrowerCoveringGivesAGluedCycleToo) {
  // Four frames past each end: pentatopes up to 8 (Δ) in circumradius.
  expect_periodic_delaunay_glued_at_the_seam(4);
}

TEST(PeriodicTime, ACoveringCutOffTwoFramesPastItsTrustedBandGivesAGluedCycleToo) {
  // A trusted band of 4Δ (pentatopes up to 2Δ in circumradius, as in a job), and two frames
  // past it.
  expect_periodic_delaunay_glued_at_the_seam(6, 4);
}

// The covering a job takes (refine_periodic): its trusted band, and one frame more.
std::pair<std::size_t, std::size_t> job_covering_frames() {
  const domain::LabelImage4 cycle =
      domain::beating_ventricle_phantom({50, 50, 22, 12}, {3.54, 3.54, 12, 8});
  const auto band = static_cast<std::size_t>(std::lround(periodic_trusted_reach(8) / 8));
  return {periodic_margin_frames(cycle, 8), band};
}

TEST(PeriodicTime, TheJobsCoveringOneFramePastItsTrustedBandGivesAGluedCycle) {
  const auto [margin, trusted] = job_covering_frames();
  EXPECT_EQ(margin, trusted + 1);
  expect_periodic_delaunay_glued_at_the_seam(margin, trusted);
}

// On threads, every point's copies are claimed and committed as one operation (or, where their
// regions touch, the operation runs alone): the covering stays periodic and Delaunay.
TEST(PeriodicTime, OnThreadsTheCoveringIsPeriodicDelaunayAndTheCycleIsGluedAtTheSeam) {
  const auto [margin, trusted] = job_covering_frames();
  expect_periodic_delaunay_glued_at_the_seam(margin, trusted, 2);
}

TEST(PeriodicTime, OnMoreThreadsThanCoresTheCoveringIsPeriodicDelaunayToo) {
  expect_periodic_delaunay_glued_at_the_seam(12, 0, 4);
}

TEST(PeriodicTime, ABallThatLivesAcrossTheEndOfTheCycleIsOnePieceOfTheGluedMesh) {
  domain::LabelImage4 cycle = domain::appearing_ball_phantom({36, 24, 24, 12}, {1, 1, 1, 1}, 10);
  cycle.set_time_spacing(2);
  RefineParams params;
  params.delta = 2;
  std::vector<std::string> warnings;
  const RefineResult r = refine_periodic(cycle, params, nullptr, &warnings);
  expect_glued_at_the_seam(r.mesh);
  const FidelityCertificate certificate = certify(r.mesh, cycle);
  EXPECT_TRUE(certificate.defects().empty()) << ::testing::PrintToString(certificate.defects());
  for (const LabelFidelity& l : certificate.labels) {
    EXPECT_EQ(l.image_pieces, 1u) << l.label;
    EXPECT_EQ(l.mesh_pieces, 1u) << l.label;
  }
  // The ball is gone from frame 4 to frame 10, and there from frame 11 to frame 3.
  const auto volume_of_ball = [&](std::size_t frame) {
    const auto v = mesh::slice_volumes(r.mesh, cycle.voxel_center(0, 0, 0, frame)[3]);
    return v.count(2) ? v.at(2) : 0.0;
  };
  EXPECT_EQ(volume_of_ball(6), 0.0);
  EXPECT_GT(volume_of_ball(0), 100.0);
  EXPECT_GT(volume_of_ball(11), 10.0);
  const auto [ends, middle] = frame_errors(r.mesh, cycle);
  std::printf("worst frame volume error: %.3f first and last frames, %.3f the others\n", ends,
              middle);
  // Balls of at most 7 voxels at δ 2 lose up to about a seventh of their volume to the sag of
  // their facets in any frame; the frames at the seam lose no more than the others.
  EXPECT_LT(ends, middle + 0.03);
  EXPECT_LT(middle, 0.2);
}

// Pat02 as a job with `--delta 5 --time-topology periodic` prepares it (../shared/data/heart4d,
// skipped where absent), meshed at `seed`, in the job's covering or, with `margin_frames`, in one
// that reaches that far past each end of the period with a trusted band of `trusted_frames`: its
// pieces on the glued cycle are the image's, none touching, and every link is a sphere. About
// 15 s.
void expect_pat02_periodic_faithful(std::uint64_t seed, std::size_t margin_frames = 0,
                                    std::size_t trusted_frames = 0) {
  const std::filesystem::path file =
      std::filesystem::path(MESH4D_HEART_DATA_DIR) / "Pat02_mse4d_label4d.nii.gz";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "no real data: " << file << " is absent";
  domain::LabelImage4 cycle = domain::read_label_image(file.string());
  cycle.set_time_spacing(domain::automatic_time_scale(cycle, 5, true));
  domain::clean_segmentation(cycle, domain::kDefaultMinIslandVoxels);
  RefineParams params;
  params.delta = 5;
  params.seed = seed;
  RefineResult r;
  if (margin_frames == 0) {
    std::vector<std::string> warnings;
    r = refine_periodic(cycle, params, nullptr, &warnings);
  } else {
    const domain::TimePeriod period = domain::cycle_period(cycle);
    domain::LabelImage4 covering = domain::tile_cycle(cycle, margin_frames);
    domain::validate_and_close(covering);
    const domain::SurfaceOracle oracle(covering);
    params.period_start = period.start;
    params.period = period.length;
    params.period_margin = static_cast<double>(margin_frames) * cycle.spacing()[3];
    params.period_trusted = static_cast<double>(trusted_frames) * cycle.spacing()[3];
    Refiner refiner(oracle, params);
    r = refiner.run();
  }
  const FidelityCertificate certificate = certify(r.mesh, cycle);
  for (const LabelFidelity& l : certificate.labels) {
    std::printf("Pat02 periodic, seed %llu, label %u: mesh %zu pieces (%zu touching), image %zu\n",
                static_cast<unsigned long long>(seed), unsigned{l.label}, l.mesh_pieces,
                l.touching_pieces, l.image_pieces);
    EXPECT_EQ(l.mesh_pieces, l.image_pieces) << "label " << l.label;
    EXPECT_EQ(l.touching_pieces, 0u) << "label " << l.label;
  }
  EXPECT_TRUE(certificate.defects().empty()) << ::testing::PrintToString(certificate.defects());
}

// A small myocardium piece near the seam (frames 0–5) meets the large one across a voxel
// corner, and its copy one period later lies near the covering's upper end. The manifold steps
// once mended links of the copy's vertices past the trusted band (the cut-off's links), and the
// labels they moved went to the middle sheet through the twins: at seed 7 two vertices at
// t ≈ 20 were non-manifold, and two myocardium pieces touched there.
TEST(PeriodicTime, APatientsIslandNearTheSeamStaysApartAndManifold) {
  expect_pat02_periodic_faithful(7);
}

// In a covering of 6 frames (the trusted band 4), the same island's copy one period later fills
// the upper margin up to its cut-off end. The piece matching once cut that copy off the wall
// first, which reached the middle sheet only in part, and then found no cut for the middle
// sheet's island: at seed 4 the island was joined to the wall (two mesh pieces against the
// image's three).
TEST(PeriodicTime, AnIslandIsCutOffInTheMiddleSheetNotWhereItsCopyFillsAMargin) {
  expect_pat02_periodic_faithful(4, 6, 4);
}

}  // namespace
}  // namespace mesh4d::refine
