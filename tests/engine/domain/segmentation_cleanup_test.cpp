// The cleanup before meshing: small face-connected pieces of any label, and small background
// pockets, take their neighbors' label; the outside (background at the border) stays; the
// report names what went. On the patients (skipped where absent) it prints the pieces' sizes.
#include "domain/segmentation_cleanup.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "domain/face_components.h"
#include "domain/image_io.h"
#include "domain/label_census.h"
#include "domain/phantoms.h"

namespace mesh4d::domain {
namespace {

// A 12⁴ image: a block of label 1 (2..9 on every axis) with a block of label 2 inside it.
LabelImage4 blocks() {
  LabelImage4 image({12, 12, 12, 12}, {1, 1, 1, 1});
  for (std::size_t t = 2; t < 10; ++t)
    for (std::size_t z = 2; z < 10; ++z)
      for (std::size_t y = 2; y < 10; ++y)
        for (std::size_t x = 2; x < 10; ++x)
          image.set(x, y, z, t, x >= 4 && x < 8 && y >= 4 && y < 8 ? 2 : 1);
  return image;
}

std::size_t pieces_of(const LabelImage4& image, Label l) {
  for (const auto& per : take_census(image).labels)
    if (per.label == l) return per.face_components;  // the cleanup's connectivity
  return 0;
}

TEST(SegmentationCleanup, IslandsAndHolesBelowTheThresholdGoAndAreReported) {
  LabelImage4 image = blocks();
  image.set(0, 11, 5, 5, 2);  // an island of one voxel in the outside (on the border)
  image.set(1, 1, 1, 1, 1);   // a one-voxel island of label 1 in the background
  image.set(3, 3, 3, 3, 0);   // a hole of one voxel in label 1
  image.set(3, 3, 4, 3, 0);   // ... of two voxels
  image.set(5, 5, 5, 5, 1);   // an island of label 1 inside label 2
  ASSERT_EQ(pieces_of(image, 1), 3u);
  ASSERT_EQ(pieces_of(image, 2), 2u);
  const CleanupReport report = clean_segmentation(image, 8);
  EXPECT_EQ(pieces_of(image, 1), 1u);
  EXPECT_EQ(pieces_of(image, 2), 1u);
  EXPECT_EQ(image.at(0, 11, 5, 5), 0);
  EXPECT_EQ(image.at(1, 1, 1, 1), 0);
  EXPECT_EQ(image.at(3, 3, 3, 3), 1);
  EXPECT_EQ(image.at(3, 3, 4, 3), 1);
  EXPECT_EQ(image.at(5, 5, 5, 5), 2);
  std::map<Label, CleanupReport::PerLabel> by_label;
  for (const auto& l : report.labels) by_label[l.label] = l;
  ASSERT_EQ(by_label.size(), 3u);
  EXPECT_EQ(by_label[0].pieces, 1u);  // the two-voxel hole
  EXPECT_EQ(by_label[0].voxels, 2u);
  EXPECT_EQ(by_label[1].pieces, 2u);
  EXPECT_EQ(by_label[2].pieces, 1u);
  const auto warnings = report.warnings(8);
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_NE(warnings[0].find("holes of background filled"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("label 1: 2 islands removed (2 voxels"), std::string::npos)
      << warnings[1];
}

TEST(SegmentationCleanup, NothingChangesAtThresholdZeroOrWithoutSmallPieces) {
  LabelImage4 image = blocks();
  image.set(1, 1, 1, 1, 1);
  const LabelImage4 before = image;
  EXPECT_TRUE(clean_segmentation(image, 0).labels.empty());
  EXPECT_TRUE(clean_segmentation(image, 1).labels.empty());  // no piece is under one voxel
  for (std::size_t i = 0; i < image.voxel_count(); ++i) ASSERT_EQ(image.at(i), before.at(i));
}

// Diagonal-only contacts are not face contacts: a checkerboard of one-voxel cubes is as many
// pieces as cubes, and every one is small.
TEST(SegmentationCleanup, ACheckerboardIsAllIslands) {
  LabelImage4 image({8, 8, 8, 8}, {1, 1, 1, 1});
  std::size_t cubes = 0;
  for (std::size_t t = 2; t < 6; ++t)
    for (std::size_t z = 2; z < 6; ++z)
      for (std::size_t y = 2; y < 6; ++y)
        for (std::size_t x = 2; x < 6; ++x)
          if ((x + y + z + t) % 2 == 0) image.set(x, y, z, t, 1), ++cubes;
  EXPECT_EQ(pieces_of(image, 1), cubes);
  const CleanupReport report = clean_segmentation(image, 2);
  ASSERT_EQ(report.labels.size(), 2u);  // the pockets between the cubes are holes too
  EXPECT_GT(report.labels[0].pieces + report.labels[1].pieces, 0u);
}

// Two blocks of label 1 that meet only along a diagonal edge (x and y both step), in blocks of
// two voxels of label 1 and two of background: the tie goes to label 1, so the label function
// joins them, and the cleanup makes that a face contact (one voxel per contact, one contact per
// pair of pieces). The diagonal island's contacts are in blocks mostly of label 1, where the
// label function keeps label 2's pieces apart: nothing is filled there.
TEST(SegmentationCleanup, DiagonalContactsTheLabelFunctionJoinsBecomeFaceContacts) {
  LabelImage4 image({10, 10, 8, 8}, {1, 1, 1, 1});
  for (std::size_t t = 2; t < 6; ++t)
    for (std::size_t z = 2; z < 6; ++z)
      for (std::size_t y = 2; y < 8; ++y)
        for (std::size_t x = 2; x < 8; ++x)
          if ((x < 5 && y < 5) || (x >= 5 && y >= 5)) image.set(x, y, z, t, 1);
  ASSERT_EQ(take_census(image).labels.at(0).face_components, 2u);
  ASSERT_EQ(take_census(image).labels.at(0).components, 1u);
  const CleanupReport report = clean_segmentation(image, 2);
  const auto& filled = report.diagonal.labels.at(1);
  EXPECT_EQ(filled.contacts, 1u);
  EXPECT_EQ(filled.voxels, 1u);
  EXPECT_EQ(filled.left, 0u);
  EXPECT_EQ(take_census(image).labels.at(0).face_components, 1u);
  const auto warnings = report.warnings(2);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("label 1: 1 diagonal contacts"), std::string::npos) << warnings[0];

  LabelImage4 island = make_phantom("diagonal-island");
  clean_segmentation(island, kDefaultMinIslandVoxels);
  const LabelCensus census = take_census(island);
  EXPECT_EQ(census.labels.at(1).face_components, 2u);
  EXPECT_EQ(census.labels.at(1).components, 2u);
}

// After the cleanup each label's face-connected pieces are its label function's pieces, on
// every phantom and on random images, except where the report says a contact was left (a
// path would have split another label).
TEST(SegmentationCleanup, FacePiecesAreTheLabelFunctionsAfterIt) {
  std::vector<LabelImage4> images;
  for (const std::string& name : phantom_names()) images.push_back(make_phantom(name));
  std::mt19937 rng(5);
  for (int trial = 0; trial < 40; ++trial) {
    LabelImage4 image({7, 6, 5, 4}, {1, 1, 1, 1});
    std::bernoulli_distribution on(0.3 + 0.01 * trial);
    std::uniform_int_distribution<int> label(1, trial % 3 + 1);
    for (std::size_t i = 0; i < image.voxel_count(); ++i)
      if (on(rng)) image.set(i, static_cast<Label>(label(rng)));
    images.push_back(std::move(image));
  }
  std::size_t checked = 0, filled = 0;
  for (LabelImage4& image : images) {
    const CleanupReport report = clean_segmentation(image, 1);
    for (const auto& per : take_census(image).labels) {
      const auto it = report.diagonal.labels.find(per.label);
      if (it != report.diagonal.labels.end()) {
        filled += it->second.contacts;
        if (it->second.left > 0) continue;
      }
      ++checked;
      EXPECT_EQ(per.face_components, per.components) << "label " << per.label;
    }
  }
  std::printf("%zu labels checked, %zu contacts filled\n", checked, filled);
  EXPECT_GT(checked, 60u);
  EXPECT_GT(filled, 100u);
}

// Past the image's border is background, for the votes too: meshing with time caps cleans the
// image before closing it, and must get what cleaning the closed image gives.
TEST(SegmentationCleanup, AnImageIsCleanedAlikeClosedOrNot) {
  // A voxel of label 2 in a corner, among label 1: four faces on label 1, four on the border
  // (background once closed); the tie goes to the smaller label, the background.
  LabelImage4 corner({4, 4, 4, 4}, {1, 1, 1, 1});
  for (std::size_t i = 0; i < corner.voxel_count(); ++i) corner.set(i, i == 0 ? 2 : 1);
  std::vector<std::pair<std::string, LabelImage4>> images{{"corner", corner}};
  for (const char* name : {"thin-wall", "checkerboard", "island", "moving-junction"})
    images.emplace_back(name, make_phantom(name));
  images.emplace_back("ventricle", beating_ventricle_phantom({40, 40, 16, 6}, {4, 4, 12, 1}));
  for (const auto& [name, image] : images) {
    LabelImage4 closed_first = image, cleaned_first = image;
    validate_and_close(closed_first);
    clean_segmentation(closed_first, 81);
    clean_segmentation(cleaned_first, 81);
    validate_and_close(cleaned_first);
    ASSERT_EQ(closed_first.dims(), cleaned_first.dims()) << name;
    std::size_t differ = 0;
    for (std::size_t i = 0; i < closed_first.voxel_count(); ++i)
      differ += closed_first.at(i) != cleaned_first.at(i);
    EXPECT_EQ(differ, 0u) << name;
  }
  clean_segmentation(corner, 81);
  EXPECT_EQ(corner.at(0), 0) << "the corner voxel went to the background";
}

TEST(SegmentationCleanup, PatientsPiecesBySize) {
  const std::filesystem::path dir(MESH4D_HEART_DATA_DIR);
  if (!std::filesystem::exists(dir / "Pat01_mse4d_label4d.nii.gz"))
    GTEST_SKIP() << "no real data in " << dir;
  for (int patient = 1; patient <= 5; ++patient) {
    const auto file = dir / ("Pat0" + std::to_string(patient) + "_mse4d_label4d.nii.gz");
    LabelImage4 image = read_label_image(file.string());
    std::map<Label, std::map<int, int>> sizes;  // label -> (⌊log2 voxels⌋ -> pieces)
    for (const auto& p : face_pieces(image).pieces)
      if (!(p.label == 0 && p.touches_border)) {
        int bits = 0;
        while ((std::size_t{2} << bits) <= p.voxels) ++bits;
        ++sizes[p.label][bits];
      }
    std::printf("Pat0%d pieces by size (2^k voxels: count):", patient);
    for (const auto& [l, by] : sizes) {
      std::printf(" | label %u:", unsigned{l});
      for (const auto& [k, n] : by) std::printf(" %d:%d", k, n);
    }
    const CleanupReport report = clean_segmentation(image, kDefaultMinIslandVoxels);
    std::printf("\n  after cleanup at %zu:", kDefaultMinIslandVoxels);
    for (const auto& per : take_census(image).labels)
      std::printf(" label %u %zu pieces;", unsigned{per.label}, per.components);
    std::printf("\n");
    for (const auto& w : report.warnings(kDefaultMinIslandVoxels)) std::printf("  %s\n", w.c_str());
    for (const auto& p : face_pieces(image).pieces)
      if (!(p.label == 0 && p.touches_border)) {
        EXPECT_GE(p.voxels, kDefaultMinIslandVoxels) << "label " << p.label;
      }
  }
}

}  // namespace
}  // namespace mesh4d::domain
