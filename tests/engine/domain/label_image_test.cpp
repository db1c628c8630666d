#include "domain/label_image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace mesh4d::domain {
namespace {

TEST(LabelImage, StoresOneByteUntilALabelNeedsTwo) {
  LabelImage4 image({4, 3, 2, 2}, {1, 1, 1, 1});
  EXPECT_EQ(image.storage_bytes(), 48u);
  image.set(1, 2, 1, 1, 200);
  EXPECT_EQ(image.storage_bytes(), 48u);
  image.set(0, 0, 0, 0, 1000);
  EXPECT_EQ(image.storage_bytes(), 96u);
  EXPECT_EQ(image.at(1, 2, 1, 1), 200);
  EXPECT_EQ(image.at(0, 0, 0, 0), 1000);
  EXPECT_EQ(image.labels(), (std::vector<Label>{0, 200, 1000}));
}

TEST(LabelImage, PhysicalCoordinatesOfVoxelCenters) {
  LabelImage4 image({10, 10, 10, 5}, {0.5, 2, 3, 7}, {1, 2, 3, 4});
  const Point4 c = image.voxel_center(2, 3, 4, 1);
  EXPECT_EQ(c, (Point4{2, 8, 15, 11}));
  const Vec4 u = image.to_index(c);
  EXPECT_EQ(u, (Vec4{2, 3, 4, 1}));
}

TEST(LabelImage, FromRawDecodesLittleEndianAndChecksTheByteCount) {
  const std::vector<std::uint8_t> raw16 = {1, 0, 0, 1, 0, 0, 2, 0};  // 1, 256, 0, 2
  const auto image = LabelImage4::from_raw({4, 1, 1, 1}, {1, 1, 1, 1}, {0, 0, 0, 0},
                                           LabelType::uint16, raw16.data(), raw16.size());
  EXPECT_EQ(image.at(0), 1);
  EXPECT_EQ(image.at(1), 256);
  EXPECT_EQ(image.at(3), 2);
  try {
    LabelImage4::from_raw({4, 1, 1, 1}, {1, 1, 1, 1}, {0, 0, 0, 0}, LabelType::uint16, raw16.data(),
                          7);
    FAIL() << "a truncated buffer must be refused";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("7 bytes"), std::string::npos) << e.what();
  }
}

TEST(LabelImage, NegativeInt16LabelIsRefused) {
  const std::vector<std::uint8_t> raw = {1, 0, 0xff, 0xff};  // 1, -1
  EXPECT_THROW(LabelImage4::from_raw({2, 1, 1, 1}, {1, 1, 1, 1}, {0, 0, 0, 0}, LabelType::int16,
                                     raw.data(), raw.size()),
               ImageError);
}

TEST(LabelImage, BadGeometryIsRefusedWithTheAxisNamed) {
  auto message = [](auto&& make) {
    try {
      make();
    } catch (const ImageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([] {
              LabelImage4({4, 0, 4, 4}, {1, 1, 1, 1});
            }).find("along y is 0"),
            std::string::npos);
  EXPECT_NE(message([] {
              LabelImage4({4, 4, 4, 4}, {1, 1, NAN, 1});
            }).find("spacing along z"),
            std::string::npos);
  EXPECT_NE(message([] {
              LabelImage4({4, 4, 4, 4}, {1, 1, 1, 0});
            }).find("spacing along t"),
            std::string::npos);
  EXPECT_NE(message([] {
              LabelImage4({4, 4, 4, 4}, {1, 1, 1, -2});
            }).find("positive"),
            std::string::npos);
  EXPECT_NE(message([] {
              LabelImage4({4, 4, 4, 4}, {1, 1, 1, 1}, {INFINITY, 0, 0, 0});
            }).find("origin along x"),
            std::string::npos);
}

TEST(ValidateAndClose, NoForegroundIsAnError) {
  LabelImage4 image({3, 3, 3, 3}, {1, 1, 1, 1});
  EXPECT_THROW(validate_and_close(image), ImageError);
}

TEST(ValidateAndClose, TooManyLabelsIsAnError) {
  LabelImage4 image({300, 1, 1, 1}, {1, 1, 1, 1});
  for (std::size_t i = 0; i < 300; ++i) image.set(i, static_cast<Label>(i + 1));
  EXPECT_THROW(validate_and_close(image), ImageError);
}

TEST(ValidateAndClose, InteriorObjectNeedsNoPadding) {
  LabelImage4 image({5, 5, 5, 5}, {1, 1, 1, 1});
  image.set(2, 2, 2, 2, 1);
  EXPECT_TRUE(validate_and_close(image).empty());
  EXPECT_EQ(image.dims(), (Dims4{5, 5, 5, 5}));
}

TEST(ValidateAndClose, ObjectOnTheBorderIsPaddedAndKeepsItsPhysicalPlace) {
  // Present in every frame (touches t = 0 and t = 3) and at x = 0.
  LabelImage4 image({5, 5, 5, 4}, {1, 1, 2, 0.5}, {10, 0, 0, 0});
  for (std::size_t t = 0; t < 4; ++t) image.set(0, 2, 2, t, 1);
  const Point4 before = image.voxel_center(0, 2, 2, 1);
  const auto warnings = validate_and_close(image);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("along x"), std::string::npos);
  EXPECT_NE(warnings[1].find("along t"), std::string::npos);
  EXPECT_EQ(image.dims(), (Dims4{6, 5, 5, 6}));
  EXPECT_EQ(image.at(1, 2, 2, 2), 1);
  EXPECT_EQ(image.voxel_center(1, 2, 2, 2), before);
  for (std::size_t t = 0; t < 6; t += 5)
    for (std::size_t x = 0; x < 6; ++x) EXPECT_EQ(image.at(x, 2, 2, t), 0);
}

}  // namespace
}  // namespace mesh4d::domain
