// The checks of a refined mesh that the sequential and the parallel refiner's tests share.
#include "refine/refine_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "delaunay/geometry.h"
#include "delaunay/predicates.h"
#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "mesh/mesh_check.h"
#include "refine/boundary_distance.h"
#include "refine/refiner.h"

namespace mesh4d::refine {

double output_volume(const mesh::Mesh4& m, mesh::Label label) {
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

domain::LabelImage4 small_ventricle() {
  domain::LabelImage4 image =
      domain::beating_ventricle_phantom({50, 50, 22, 8}, {3.54, 3.54, 12, 1});
  image.set_time_spacing(8);
  return image;
}

std::optional<domain::LabelImage4> patient_at_papers_spacing(const std::string& name, bool closed) {
  const std::filesystem::path file =
      std::filesystem::path(MESH4D_HEART_DATA_DIR) / (name + "_mse4d_label4d.nii.gz");
  if (!std::filesystem::exists(file)) return std::nullopt;
  const auto read = domain::read_label_image(file.string());
  const auto& d = read.dims();
  domain::LabelImage4 image({d[0], d[1], d[2], 15}, {1.77, 1.77, 6, 1});
  for (std::size_t i = 0; i < image.voxel_count(); ++i)
    if (read.at(i) != 0) image.set(i, read.at(i));
  if (closed) domain::validate_and_close(image);
  return image;
}

void expect_only_manifold_warning(const RefineResult& r) {
  std::size_t manifold = 0;
  for (const std::string& w : r.warnings) {
    const bool is_manifold = w.find("link that is not a 2-sphere") != std::string::npos;
    manifold += is_manifold;
    EXPECT_TRUE(is_manifold) << w;
  }
  EXPECT_EQ(manifold, r.non_manifold_left > 0 ? 1u : 0u);
}

void expect_fidelity(const mesh::Mesh4& m, const domain::SurfaceOracle& oracle,
                     const std::vector<domain::Label>& labels, double max_distance,
                     double vertex_offset) {
  std::size_t off_surface = 0;
  double farthest = 0;  // of the vertices off ∂Ω
  for (const auto& b : m.boundary)
    for (auto v : b.vertices) {
      ASSERT_EQ(m.vertex_kinds[v], mesh::VertexKind::feature) << "boundary vertex " << v;
      std::vector<double> weights;
      for (auto l : labels) weights.push_back(oracle.cut_value(m.vertices[v], l, 65535));
      std::sort(weights.rbegin(), weights.rend());
      if (weights[0] - weights[1] <= 1e-6) continue;
      // Off ∂Ω: only as far as the sag offset moved it. Both closest-point searches give an upper
      // bound (the descent can stop at a farther point where ∂Ω folds, as between two close
      // gaps), hence the nearer of the two and a tenth of slack.
      double d = std::numeric_limits<double>::infinity();
      for (auto mode :
           {domain::SurfaceOracle::CfpMode::descent, domain::SurfaceOracle::CfpMode::ray}) {
        const domain::SurfacePoint z = oracle.closest_surface_point(m.vertices[v], mode);
        if (z.inner != z.outer) d = std::min(d, distance(z.point, m.vertices[v]));
      }
      farthest = std::max(farthest, d);
      off_surface += !(d <= 1.1 * vertex_offset + 1e-9);
    }
  std::printf("boundary vertices off ∂Ω: at most %.3f away (sag offset up to %.3f)\n", farthest,
              vertex_offset);
  EXPECT_EQ(off_surface, 0u);
  const mesh::BoundaryCheck check = mesh::check_boundary(m);
  // Every boundary tetrahedron: a sample of one in fourteen missed Pat05's farthest.
  const BoundaryDistance distance =
      measure_boundary_distance(m, oracle, std::numeric_limits<std::size_t>::max());
  std::printf(
      "boundary triangles: %zu, in an odd number of facets: %zu, pinched (4 or more): %zu; "
      "distance to ∂Ω over %zu samples: max %.3f mean %.3f\n",
      check.triangles, check.odd, check.pinched, distance.samples, distance.max, distance.mean);
  EXPECT_EQ(check.non_feature_uses, 0u);
  EXPECT_EQ(check.odd, 0u);
  EXPECT_EQ(check.pinched, 0u);
  EXPECT_GT(distance.samples, 0u);
  // The bounds were measured on ∂Ω's own samples; the offset moves a facet's points by at most
  // its vertices' largest move.
  EXPECT_LE(distance.max, max_distance + vertex_offset);
}

std::size_t unmeshed_components(const domain::LabelImage4& image, const mesh::Mesh4& m,
                                std::size_t* components) {
  const auto& d = image.dims();
  const std::size_t stride[4] = {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
  std::vector<std::int64_t> component(image.voxel_count(), -1);
  std::size_t count = 0;
  for (std::size_t seed = 0; seed < image.voxel_count(); ++seed) {
    if (image.at(seed) == 0 || component[seed] >= 0) continue;
    std::vector<std::size_t> stack{seed};
    component[seed] = static_cast<std::int64_t>(count);
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      std::size_t rest = i;
      for (int a = 3; a >= 0; --a) {
        const std::size_t coord = rest / stride[a];
        rest %= stride[a];
        for (int step : {-1, 1}) {
          if ((step < 0 && coord == 0) || (step > 0 && coord + 1 == d[a])) continue;
          const std::size_t j = step < 0 ? i - stride[a] : i + stride[a];
          if (image.at(j) != image.at(seed) || component[j] >= 0) continue;
          component[j] = static_cast<std::int64_t>(count);
          stack.push_back(j);
        }
      }
    }
    ++count;
  }
  std::vector<bool> meshed(count, false);
  for (std::size_t p = 0; p < m.pentatopes.size(); ++p) {
    delaunay::Simplex4 s;
    for (int k = 0; k < 5; ++k) s[k] = m.vertices[m.pentatopes[p][k]];
    const auto at = image.to_index(delaunay::circumcenter(s));
    std::size_t index = 0;
    bool in_image = true;
    for (int a = 0; a < 4; ++a) {
      const double x = std::round(at[a]);
      if (x < 0 || x >= static_cast<double>(d[a])) in_image = false;
      index += in_image ? static_cast<std::size_t>(x) * stride[a] : 0;
    }
    if (in_image && image.at(index) == m.labels[p] && component[index] >= 0)
      meshed[static_cast<std::size_t>(component[index])] = true;
  }
  *components = count;
  return static_cast<std::size_t>(std::count(meshed.begin(), meshed.end(), false));
}

namespace {

class StopAfter : public ProgressSink {
 public:
  void on_progress(const Progress& p) override { last = p; }
  bool should_abort() override { return ++polls > 2; }
  Progress last;
  int polls = 0;
};

}  // namespace

void expect_cancellation_and_budget_stop(unsigned threads) {
  const auto image = domain::hypersphere_phantom({32, 32, 32, 32}, {1, 1, 1, 1}, 12);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 2;
  params.threads = threads;
  StopAfter sink;
  EXPECT_THROW(Refiner(oracle, params).run(&sink), Cancelled);
  params.vertex_budget = 200;
  EXPECT_THROW(Refiner(oracle, params).run(), BudgetExceeded);
}

void expect_moves_kept_quality(const RefineResult& moved, const RefineResult& unmoved,
                               const RefineParams& params) {
  const mesh::Mesh4& a = moved.mesh;
  for (const auto& p : a.pentatopes)
    ASSERT_GT(delaunay::orient4(a.vertices[p[0]], a.vertices[p[1]], a.vertices[p[2]],
                                a.vertices[p[3]], a.vertices[p[4]]),
              0);
  EXPECT_GE(moved.stats.normalized_volume.min,
            std::min(params.sliver_bound, unmoved.stats.normalized_volume.min));
  EXPECT_LE(moved.stats.radius_edge_ratio.max,
            std::max(params.radius_edge_bound, unmoved.stats.radius_edge_ratio.max));
}

}  // namespace mesh4d::refine
