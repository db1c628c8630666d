#include "domain/phantoms.h"

#include <gtest/gtest.h>

#include <queue>

namespace mesh4d::domain {
namespace {

// Connected components of the foreground within one frame (6-connectivity in 3D).
int components_in_frame(const LabelImage4& image, std::size_t t) {
  const Dims4& d = image.dims();
  std::vector<char> seen(d[0] * d[1] * d[2], 0);
  int count = 0;
  for (std::size_t start = 0; start < seen.size(); ++start) {
    if (seen[start] || image.at(start + t * seen.size()) == 0) continue;
    ++count;
    std::queue<std::size_t> q;
    q.push(start);
    seen[start] = 1;
    while (!q.empty()) {
      const std::size_t i = q.front();
      q.pop();
      const std::size_t x = i % d[0], y = i / d[0] % d[1], z = i / (d[0] * d[1]);
      const long steps[3] = {1, long(d[0]), long(d[0] * d[1])};
      const std::size_t c[3] = {x, y, z};
      for (int a = 0; a < 3; ++a)
        for (int s = -1; s <= 1; s += 2) {
          if ((s < 0 && c[a] == 0) || (s > 0 && c[a] + 1 == d[a])) continue;
          const std::size_t j = i + s * steps[a];
          if (!seen[j] && image.at(j + t * seen.size()) != 0) seen[j] = 1, q.push(j);
        }
    }
  }
  return count;
}

TEST(Phantoms, EveryNamedPhantomHasForegroundAndTheDocumentedLabels) {
  for (const auto& name : phantom_names()) {
    const LabelImage4 image = make_phantom(name);
    const auto labels = image.labels();
    if (name == "ventricle" || name == "thin-wall" || name == "corner-contact" ||
        name == "diagonal-island" || name == "appearing-ball")
      EXPECT_EQ(labels, (std::vector<Label>{0, 1, 2})) << name;
    else if (name == "moving-junction")
      EXPECT_EQ(labels, (std::vector<Label>{0, 1, 2, 3})) << name;
    else
      EXPECT_EQ(labels, (std::vector<Label>{0, 1})) << name;
  }
  EXPECT_THROW(make_phantom("teapot"), std::invalid_argument);
}

TEST(Phantoms, VentricleHasThePapersSizeAndContractsThenRelaxes) {
  const LabelImage4 v = beating_ventricle_phantom();
  EXPECT_EQ(v.dims(), (Dims4{100, 100, 44, 15}));
  auto pool = [&](std::size_t t) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < 100 * 100 * 44; ++i) n += v.at(i + t * 100 * 100 * 44) == 1;
    return n;
  };
  EXPECT_LT(pool(7), 0.7 * pool(0));  // end-systole: much smaller blood pool
  EXPECT_NEAR(double(pool(14)), double(pool(1)), 0.05 * pool(1));  // back near end-diastole
}

TEST(Phantoms, BlobsMergeAndSplitOverTime) {
  const LabelImage4 b = merging_blobs_phantom();
  const std::size_t last = b.dims()[3] - 1;
  EXPECT_EQ(components_in_frame(b, 0), 2);
  EXPECT_EQ(components_in_frame(b, last / 2), 1);
  EXPECT_EQ(components_in_frame(b, last), 2);
}

}  // namespace
}  // namespace mesh4d::domain
