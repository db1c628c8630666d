// The surface oracle on voxelized analytic shapes.
//
// What "closest" is checked against: the oracle's surface is the zero set of the interpolated
// label function, which a voxelized sphere only approximates (a staircase within half a voxel).
// So cfp is checked (1) to lie on that zero set, |f| ≤ 1e-9, (2) to be no farther from x than the
// closest point of the zero set found by brute force (a dense fan of rays) plus 0.25 of the
// smallest spacing, and (3) to be within 0.6 voxel of the analytic sphere, the voxelization's
// own error. The 0.05-voxel target is not met: that zero set is bumpy at the voxel scale,
// with near-ties between distant points, and only a smoother cut function would get there.
#include "domain/surface_oracle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "domain/phantoms.h"

namespace mesh4d::domain {
namespace {

double dist(const Point4& a, const Point4& b) {
  double s = 0;
  for (int i = 0; i < 4; ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s);
}

Point4 center_of(const LabelImage4& image) {
  Point4 c;
  for (int a = 0; a < 4; ++a)
    c[a] = image.origin()[a] + 0.5 * double(image.dims()[a] - 1) * image.spacing()[a];
  return c;
}

// Closest point of the zero set to x by brute force, for a star-shaped object around `center`:
// crossings along a fan of 17³ rays around the direction of x, then a finer fan around the best.
Point4 brute_force_closest(const SurfaceOracle& oracle, const Point4& center, const Point4& x,
                           double reach) {
  Point4 dir{x[0] - center[0], x[1] - center[1], x[2] - center[2], x[3] - center[3]};
  Point4 best_point = center;
  double best = INFINITY;
  double width = 0.3;
  for (int round = 0; round < 3; ++round, width /= 6) {
    // Two vectors... a basis of the hyperplane normal to dir, by Gram-Schmidt on the axes.
    double n = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2] + dir[3] * dir[3]);
    Point4 u{dir[0] / n, dir[1] / n, dir[2] / n, dir[3] / n};
    std::vector<Point4> basis;
    for (int a = 0; a < 4 && basis.size() < 3; ++a) {
      Point4 e{0, 0, 0, 0};
      e[a] = 1;
      auto sub = [&](const Point4& b) {
        const double p = e[0] * b[0] + e[1] * b[1] + e[2] * b[2] + e[3] * b[3];
        for (int i = 0; i < 4; ++i) e[i] -= p * b[i];
      };
      sub(u);
      for (const auto& b : basis) sub(b);
      const double en = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
      if (en < 0.3) continue;
      for (double& c : e) c /= en;
      basis.push_back(e);
    }
    Point4 round_best_dir = u;
    for (int i = -8; i <= 8; ++i)
      for (int j = -8; j <= 8; ++j)
        for (int k = -8; k <= 8; ++k) {
          Point4 r;
          for (int a = 0; a < 4; ++a)
            r[a] = u[a] + width / 8 * (i * basis[0][a] + j * basis[1][a] + k * basis[2][a]);
          const Point4 far{center[0] + reach * r[0], center[1] + reach * r[1],
                           center[2] + reach * r[2], center[3] + reach * r[3]};
          const auto z = oracle.first_crossing(center, far);
          if (!z) continue;
          const double d = dist(z->point, x);
          if (d < best) best = d, best_point = z->point, round_best_dir = r;
        }
    dir = round_best_dir;
  }
  return best_point;
}

void check_cfp_on_sphere(const LabelImage4& image, double radius, std::uint64_t seed, int queries) {
  const SurfaceOracle oracle(image);
  const Point4 c = center_of(image);
  double voxel = 0;
  for (double s : image.spacing()) voxel = std::max(voxel, s);
  double min_spacing = voxel;
  for (double s : image.spacing()) min_spacing = std::min(min_spacing, s);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> r(0.3 * radius, 1.6 * radius);
  double worst_analytic = 0, worst_gap = 0;
  for (int q = 0; q < queries; ++q) {
    Point4 d{g(rng), g(rng), g(rng), g(rng)};
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + d[3] * d[3]);
    const double rad = r(rng);
    const Point4 x{c[0] + rad * d[0] / n, c[1] + rad * d[1] / n, c[2] + rad * d[2] / n,
                   c[3] + rad * d[3] / n};
    const SurfacePoint z = oracle.closest_surface_point(x);
    ASSERT_NE(z.inner, z.outer) << "query " << q;
    EXPECT_LE(std::abs(oracle.cut_value(z.point, z.inner, z.outer)), 1e-9) << "query " << q;
    const Point4 ref = brute_force_closest(oracle, c, x, 2 * radius);
    const double gap = dist(x, z.point) - dist(x, ref);
    EXPECT_LE(gap, 0.25 * min_spacing) << "query " << q << " at " << rad;
    worst_gap = std::max(worst_gap, gap);
    worst_analytic = std::max(worst_analytic, std::abs(dist(z.point, c) - radius));
  }
  EXPECT_LE(worst_analytic, 0.6 * voxel);
  ::testing::Test::RecordProperty("worst_distance_to_analytic_sphere",
                                  std::to_string(worst_analytic));
  std::printf(
      "cfp: worst excess distance over brute force %.3f, worst distance to the analytic "
      "sphere %.3f (largest spacing %.2f)\n",
      worst_gap, worst_analytic, voxel);
}

TEST(SurfaceOracle, LabelAtVoxelCentersIsTheVoxelLabel) {
  const LabelImage4 image = beating_ventricle_phantom({30, 30, 16, 6}, {2, 2, 4, 1});
  const SurfaceOracle oracle(image);
  for (std::size_t i = 0; i < image.voxel_count(); i += 7) {
    const Dims4& d = image.dims();
    std::size_t r = i, c[4];
    for (int a = 0; a < 4; ++a) c[a] = r % d[a], r /= d[a];
    ASSERT_EQ(oracle.label_at(image.voxel_center(c[0], c[1], c[2], c[3])), image.at(i));
  }
  EXPECT_EQ(oracle.label_at({-100, -100, -100, -100}), 0);  // outside the image: background
}

TEST(SurfaceOracle, CfpOnAVoxelizedSphere) {
  check_cfp_on_sphere(hypersphere_phantom({28, 28, 28, 28}, {1, 1, 1, 1}, 10), 10, 1, 25);
}

TEST(SurfaceOracle, CfpWithAnisotropicSpacing) {
  check_cfp_on_sphere(hypersphere_phantom({40, 30, 14, 24}, {0.6, 0.8, 1.77, 1.0}, 9), 9, 2, 20);
}

TEST(SurfaceOracle, CfpNearTheImageBorder) {
  // The sphere reaches within one voxel of every face; queries also come from outside the image.
  LabelImage4 image = hypersphere_phantom({24, 24, 24, 24}, {1, 1, 1, 1}, 10.6);
  const SurfaceOracle oracle(image);
  const Point4 c = center_of(image);
  for (int a = 0; a < 4; ++a)
    for (double side : {-1.0, 1.0}) {
      Point4 x = c;
      x[a] += side * 13.0;  // beyond the last voxel center along this axis
      const SurfacePoint z = oracle.closest_surface_point(x);
      EXPECT_LE(std::abs(oracle.cut_value(z.point, z.inner, z.outer)), 1e-9);
      EXPECT_NEAR(dist(z.point, c), 10.6, 0.6);
      EXPECT_LE(dist(x, z.point), 13.0 - 10.6 + 0.6);
    }
}

TEST(SurfaceOracle, FindsLabelToLabelInterfaces) {
  // Closed in time by padding; x in the blood pool, 5 mm from the myocardium and farther from
  // the time caps.
  LabelImage4 image = beating_ventricle_phantom({50, 50, 22, 12}, {3.5, 3.5, 12, 1});
  validate_and_close(image);
  const SurfaceOracle oracle(image);
  Point4 x = center_of(image);
  x[0] += 12;                        // the cavity radius is about 17 mm at mid-cycle
  ASSERT_EQ(oracle.label_at(x), 1);  // the blood pool
  const SurfacePoint z = oracle.closest_surface_point(x);
  EXPECT_EQ(z.inner, 1);
  EXPECT_EQ(z.outer, 2);  // the myocardium, not the background
  EXPECT_LE(std::abs(oracle.cut_value(z.point, 1, 2)), 1e-9);
}

TEST(SurfaceOracle, RayModeBracketsTheSurface) {
  // The refiner's R1 question: a bracket around ∂Ω (its ends have the labels it names, at most
  // kRankTolerance of the smallest spacing apart), then the point pinpointed on the zero set. Three
  // labels with their offsets, anisotropic spacing, queries from everywhere near the object.
  LabelImage4 image = beating_ventricle_phantom({50, 50, 22, 12}, {3.5, 3.5, 12, 1});
  validate_and_close(image);
  const SurfaceOracle oracle(image);
  const Point4 c = center_of(image);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const double min_spacing = 1;  // the time axis
  int found = 0;
  for (int q = 0; q < 400; ++q) {
    const Point4 x{c[0] + 40 * u(rng), c[1] + 40 * u(rng), c[2] + 60 * u(rng), c[3] + 8 * u(rng)};
    const auto k = oracle.closest_surface_bracket(x);
    if (!k) continue;
    ++found;
    EXPECT_EQ(oracle.label_at(k->a), k->label_a) << "query " << q;
    EXPECT_EQ(oracle.label_at(k->b), k->label_b) << "query " << q;
    EXPECT_EQ(k->label_a, oracle.label_at(x)) << "query " << q;  // x's side first
    EXPECT_LE(dist(k->a, k->b), 1.001 * SurfaceOracle::kRankTolerance * min_spacing)
        << "query " << q;
    const SurfacePoint z = oracle.pinpoint(*k);
    EXPECT_LE(std::abs(oracle.cut_value(z.point, z.inner, z.outer)), 1e-9) << "query " << q;
    // Within about a voxel of the closest point the descent finds.
    const SurfacePoint d = oracle.closest_surface_point(x);
    EXPECT_LE(dist(x, z.point), dist(x, d.point) + 12) << "query " << q;
  }
  EXPECT_GT(found, 350);
}

// A caller that drops every point within `reach` of `q` (both ends of a segment: the ball is
// convex); it counts what it was asked.
class DropNear final : public SurfaceOracle::Dismissal {
 public:
  DropNear(const Point4& q, double reach) : q_(q), reach_(reach) {}
  bool drops(const Point4& a, const Point4& b) const override {
    ++asked;
    return dist(a, q_) < reach_ && dist(b, q_) < reach_;
  }
  mutable int asked = 0;

 private:
  Point4 q_;
  double reach_;
};

TEST(SurfaceOracle, DismissedSearchesDropOnlyWhatTheCallerWouldDrop) {
  // Where the search stops early, the answer it would have given lies where the caller drops
  // everything; where it does not, the answer is the same bracket as without a dismissal.
  LabelImage4 image = hypersphere_phantom({24, 24, 24, 24}, {1, 1, 1, 1}, 8);
  validate_and_close(image);
  const SurfaceOracle oracle(image);
  const Point4 c = center_of(image);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int dropped_count = 0, kept_count = 0;
  for (int q = 0; q < 4000; ++q) {
    // Near ∂Ω, as the circumcenters the refiner asks about: the ray's crossing often wins.
    const Point4 y{c[0] + 40 * u(rng), c[1] + 40 * u(rng), c[2] + 60 * u(rng), c[3] + 8 * u(rng)};
    const auto near = oracle.closest_surface_bracket(y);
    if (!near) continue;
    const Point4 n = near->middle().point;
    const Point4 x{n[0] + 6 * u(rng), n[1] + 6 * u(rng), n[2] + 6 * u(rng), n[3] + u(rng)};
    const auto plain = oracle.closest_surface_bracket(x);
    if (!plain) continue;
    // A ball whose sphere passes near the answer: both outcomes happen, and a dismissal
    // asked about the wrong places drops answers it should not.
    const Point4 m = plain->middle().point;
    const Point4 center{m[0] + 4 * u(rng), m[1] + 4 * u(rng), m[2] + 4 * u(rng), m[3] + u(rng)};
    const DropNear dismissal(center, dist(center, m) + 1.5 * u(rng));
    bool dropped = false;
    const auto k = oracle.closest_surface_bracket(x, oracle.facts(x), &dismissal, &dropped);
    EXPECT_GT(dismissal.asked, 0) << "query " << q;
    if (dropped) {
      ++dropped_count;
      EXPECT_FALSE(k.has_value());
      EXPECT_TRUE(dismissal.drops(m, m)) << "query " << q << ": dropped a kept answer";
    } else {
      ++kept_count;
      ASSERT_TRUE(k.has_value()) << "query " << q;
      EXPECT_EQ(k->a, plain->a) << "query " << q;
      EXPECT_EQ(k->b, plain->b) << "query " << q;
      EXPECT_EQ(k->label_a, plain->label_a) << "query " << q;
      EXPECT_EQ(k->label_b, plain->label_b) << "query " << q;
    }
  }
  EXPECT_GT(dropped_count, 500);
  EXPECT_GT(kept_count, 500);
}

TEST(SurfaceOracle, RayWalksThatGiveUpGiveTheSameAnswers) {
  // A ray's walk stops where its crossing could only lose to an edge crossing: the answers are
  // those of full walks, near ∂Ω (where the ray sometimes wins) and far from it.
  LabelImage4 image = beating_ventricle_phantom({50, 50, 22, 12}, {3.5, 3.5, 12, 1});
  validate_and_close(image);
  SurfaceOracle full(image), short_walks(image);
  full.set_ray_give_up(false);
  const Point4 c = center_of(image);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  int compared = 0, rays = 0;
  for (int q = 0; q < 3000; ++q) {
    Point4 x{c[0] + 40 * u(rng), c[1] + 40 * u(rng), c[2] + 60 * u(rng), c[3] + 8 * u(rng)};
    if (q % 2 == 1)
      if (const auto near = full.closest_surface_bracket(x)) {
        const Point4 n = near->middle().point;
        x = {n[0] + 3 * u(rng), n[1] + 3 * u(rng), n[2] + 6 * u(rng), n[3] + u(rng)};
      }
    const auto a = full.closest_surface_bracket(x), b = short_walks.closest_surface_bracket(x);
    ASSERT_EQ(a.has_value(), b.has_value()) << "query " << q;
    if (!a) continue;
    ++compared;
    int axes = 0;  // a ray's bracket, not an edge's
    for (int k = 0; k < 4; ++k) axes += a->a[k] != a->b[k];
    rays += axes > 1;
    EXPECT_EQ(a->a, b->a) << "query " << q;
    EXPECT_EQ(a->b, b->b) << "query " << q;
    EXPECT_EQ(a->label_a, b->label_a) << "query " << q;
  }
  EXPECT_GT(compared, 2500);
  EXPECT_GT(rays, 20);  // the ray won some
}

TEST(SurfaceOracle, FirstCrossingAlongASegment) {
  const LabelImage4 image = hypersphere_phantom({20, 20, 20, 20}, {1, 1, 1, 1}, 6);
  const SurfaceOracle oracle(image);
  const Point4 c = center_of(image);
  const auto z = oracle.first_crossing(c, {c[0] + 9, c[1], c[2], c[3]});
  ASSERT_TRUE(z.has_value());
  EXPECT_EQ(z->inner, 1);
  EXPECT_EQ(z->outer, 0);
  EXPECT_NEAR(z->point[0] - c[0], 6, 0.6);
  EXPECT_FALSE(oracle.first_crossing(c, {c[0] + 1, c[1], c[2], c[3]}).has_value());
}

TEST(SurfaceOracle, SingleLabelImageIsRefused) {
  LabelImage4 image({4, 4, 4, 4}, {1, 1, 1, 1});
  EXPECT_THROW(SurfaceOracle{image}, ImageError);
}

}  // namespace
}  // namespace mesh4d::domain
