// Triple junctions: on the ventricle phantom (pool, wall, background meet where the image is
// padded in time), every sampled point solves I_a = I_b = I_c, one of the three wins there, and
// the thinning keeps them apart.
#include "domain/junctions.h"

#include <gtest/gtest.h>

#include <cmath>

#include "domain/phantoms.h"

namespace mesh4d::domain {
namespace {

double distance(const Point4& a, const Point4& b) {
  double d = 0;
  for (int k = 0; k < 4; ++k) d += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(d);
}

TEST(Junctions, SampledPointsLieOnTheTripleJunctionAndAreThinned) {
  LabelImage4 image = beating_ventricle_phantom({50, 50, 22, 8}, {3.54, 3.54, 12, 2});
  validate_and_close(image);
  const SurfaceOracle oracle(image);
  const double spacing = 4;
  std::vector<Point4> kept;
  const auto far = [&](const Point4& p) {
    for (const Point4& q : kept)
      if (distance(p, q) < spacing) return false;
    return true;
  };
  const auto points = sample_junctions(oracle, far, [&](const Point4& p) { kept.push_back(p); });
  ASSERT_GT(points.size(), 10u);
  ASSERT_EQ(points.size(), kept.size());
  for (const auto& j : points) {
    const auto [a, b, c] = j.labels;
    EXPECT_LE(std::abs(oracle.cut_value(j.point, a, b)), 1e-12);
    EXPECT_LE(std::abs(oracle.cut_value(j.point, b, c)), 1e-12);
    const Label l = oracle.label_at(j.point);
    EXPECT_TRUE(l == a || l == b || l == c) << "label " << l;
  }
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (std::size_t k = i + 1; k < kept.size(); ++k)
      ASSERT_GE(distance(kept[i], kept[k]), spacing);
}

TEST(Junctions, TwoLabelsHaveNone) {
  LabelImage4 image = hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5);
  validate_and_close(image);
  const SurfaceOracle oracle(image);
  const auto points = sample_junctions(
      oracle, [](const Point4&) { return true; }, [](const Point4&) {});
  EXPECT_TRUE(points.empty());
}

}  // namespace
}  // namespace mesh4d::domain
