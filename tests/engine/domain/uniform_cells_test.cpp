// UniformCells against reading the 16 corners of every cell.
#include "domain/uniform_cells.h"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

namespace mesh4d::domain {
namespace {

TEST(UniformCells, AgreesWithTheCornersOfEveryCell) {
  // Blocky labels (runs of one label along x, layers along the other axes) so that both kinds
  // of cells are common; odd sizes so that the last voxel along each axis is exercised.
  const Dims4 dims{7, 5, 4, 3};
  LabelImage4 image(dims, {1, 1, 1, 1});
  std::mt19937 rng(3);
  for (std::size_t i = 0; i < image.voxel_count(); ++i)
    image.set(i, rng() % 5 == 0 ? static_cast<Label>(1 + rng() % 2) : 0);
  const UniformCells cells(image);
  int uniform = 0, mixed = 0;
  for (std::size_t t = 0; t < dims[3]; ++t)
    for (std::size_t z = 0; z < dims[2]; ++z)
      for (std::size_t y = 0; y < dims[1]; ++y)
        for (std::size_t x = 0; x < dims[0]; ++x) {
          bool expected = x + 1 < dims[0] && y + 1 < dims[1] && z + 1 < dims[2] && t + 1 < dims[3];
          for (int corner = 0; corner < 16 && expected; ++corner)
            expected = image.at(x + (corner & 1), y + (corner >> 1 & 1), z + (corner >> 2 & 1),
                                t + (corner >> 3 & 1)) == image.at(x, y, z, t);
          ASSERT_EQ(cells.uniform(image.linear_index(x, y, z, t)), expected)
              << x << ' ' << y << ' ' << z << ' ' << t;
          (expected ? uniform : mixed)++;
        }
  EXPECT_GT(uniform, 0);
  EXPECT_GT(mixed, 0);
}

TEST(UniformCells, ThreadsGiveTheSameCells) {
  // Large enough to be split among the threads: by layers along x, y and z, by offsets along t
  // (a single layer); blobs of labels so that the answer varies along every axis.
  const Dims4 dims{41, 33, 24, 13};
  LabelImage4 image(dims, {1, 1, 1, 1});
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> any(0, 40);
  std::vector<std::array<int, 5>> blobs(30);  // centre, radius
  for (auto& b : blobs)
    b = {any(rng), any(rng) % 33, any(rng) % 24, any(rng) % 13, 2 + any(rng) % 6};
  for (std::size_t t = 0; t < dims[3]; ++t)
    for (std::size_t z = 0; z < dims[2]; ++z)
      for (std::size_t y = 0; y < dims[1]; ++y)
        for (std::size_t x = 0; x < dims[0]; ++x) {
          Label l = 0;
          for (std::size_t k = 0; k < blobs.size(); ++k) {
            const auto& b = blobs[k];
            const long dx = long(x) - b[0], dy = long(y) - b[1], dz = long(z) - b[2],
                       dt = long(t) - b[3];
            if (dx * dx + dy * dy + dz * dz + dt * dt <= long(b[4]) * b[4])
              l = static_cast<Label>(1 + k % 3);
          }
          image.set(image.linear_index(x, y, z, t), l);
        }
  const UniformCells one(image, 1);
  std::size_t uniform = 0;
  for (std::size_t i = 0; i < image.voxel_count(); ++i) uniform += one.uniform(i);
  EXPECT_GT(uniform, image.voxel_count() / 4);
  EXPECT_LT(uniform, image.voxel_count());
  for (const unsigned threads : {2u, 3u, 8u}) {
    const UniformCells many(image, threads);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < image.voxel_count(); ++i)
      differ += one.uniform(i) != many.uniform(i);
    EXPECT_EQ(differ, 0u) << threads << " threads";
  }
}

TEST(UniformCells, OneLabelImageHasOnlyItsInnerCellsUniform) {
  LabelImage4 image({3, 3, 3, 3}, {1, 1, 1, 1});
  for (std::size_t i = 0; i < image.voxel_count(); ++i) image.set(i, 2);
  const UniformCells cells(image);
  EXPECT_TRUE(cells.uniform(image.linear_index(0, 0, 0, 0)));
  EXPECT_TRUE(cells.uniform(image.linear_index(1, 1, 1, 1)));
  EXPECT_FALSE(cells.uniform(image.linear_index(2, 0, 0, 0)));  // past the last voxel along x
  EXPECT_FALSE(cells.uniform(image.linear_index(0, 0, 0, 2)));  // along t
}

}  // namespace
}  // namespace mesh4d::domain
