// Reading and writing label images: round trips through every supported format, frame series,
// the clear errors for bad files, and the real cardiac images beside the repository.
#include "domain/image_io.h"

#include <gtest/gtest.h>
#include <itkImage.h>
#include <itkImageFileWriter.h>
#include <sys/resource.h>
#include <unistd.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "domain/phantoms.h"

namespace mesh4d::domain {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  // One folder per process: CTest runs the tests of this file in parallel processes. It goes
  // when the process ends (nothing in it is worth keeping: each test writes and reads back).
  struct Folder {
    fs::path dir =
        fs::temp_directory_path() / ("mesh4d-image-io-test-" + std::to_string(::getpid()));
    Folder() { fs::create_directories(dir); }
    ~Folder() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  };
  static const Folder folder;
  return (folder.dir / name).string();
}

// Writes an ITK image of any pixel type and dimension with the given values (for inputs that
// mesh4d itself never writes: 3D frames, float pixels, other formats).
template <class Pixel, unsigned Dim>
void write_itk(const std::string& path, const std::array<std::size_t, Dim>& size,
               const std::function<Pixel(std::size_t)>& value, double spacing = 1.5) {
  register_image_formats();
  using Image = itk::Image<Pixel, Dim>;
  auto image = Image::New();
  typename Image::SizeType s;
  typename Image::SpacingType sp;
  for (unsigned a = 0; a < Dim; ++a) s[a] = size[a], sp[a] = spacing;
  image->SetRegions(typename Image::RegionType(s));
  image->SetSpacing(sp);
  image->Allocate();
  for (std::size_t i = 0; i < image->GetLargestPossibleRegion().GetNumberOfPixels(); ++i)
    image->GetBufferPointer()[i] = value(i);
  auto writer = itk::ImageFileWriter<Image>::New();
  writer->SetFileName(path);
  writer->SetInput(image);
  writer->Update();
}

void expect_same(const LabelImage4& a, const LabelImage4& b) {
  ASSERT_EQ(a.dims(), b.dims());
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(a.spacing()[i], b.spacing()[i], 1e-6);
    EXPECT_NEAR(a.origin()[i], b.origin()[i], 1e-6);
  }
  std::size_t differences = 0;
  for (std::size_t i = 0; i < a.voxel_count(); ++i) differences += a.at(i) != b.at(i);
  EXPECT_EQ(differences, 0u);
}

TEST(ImageIo, NiftiRoundTripKeepsLabelsDimsAndSpacing) {
  const LabelImage4 ventricle = beating_ventricle_phantom({40, 36, 20, 6}, {1.77, 1.77, 6, 1});
  for (const char* name : {"v.nii", "v.nii.gz"}) {
    const std::string path = temp_path(name);
    write_nifti(ventricle, path);
    expect_same(ventricle, read_label_image(path));
  }
}

TEST(ImageIo, SixteenBitLabelsRoundTrip) {
  // NIfTI stores no time origin (ITK reads it as 0), so this image starts at t = 0.
  LabelImage4 image({6, 5, 4, 3}, {1, 2, 3, 4}, {-5, 0, 5, 0});
  image.set(1, 1, 1, 1, 1000);
  image.set(2, 2, 2, 2, 65535);
  const std::string path = temp_path("wide.nii.gz");
  write_nifti(image, path);
  expect_same(image, read_label_image(path));
}

TEST(ImageIo, ReadsMetaImageAndNrrdOfEveryAcceptedLabelType) {
  auto label = [](std::size_t i) { return (i % 7 == 0) ? 2 : (i % 5 == 0 ? 1 : 0); };
  write_itk<std::uint8_t, 4>(temp_path("u8.mha"), {5, 4, 3, 2}, label);
  write_itk<std::uint16_t, 4>(temp_path("u16.nrrd"), {5, 4, 3, 2}, label);
  write_itk<std::int16_t, 4>(temp_path("i16.mhd"), {5, 4, 3, 2}, label);
  for (const char* name : {"u8.mha", "u16.nrrd", "i16.mhd"}) {
    const LabelImage4 image = read_label_image(temp_path(name));
    EXPECT_EQ(image.dims(), (Dims4{5, 4, 3, 2})) << name;
    EXPECT_DOUBLE_EQ(image.spacing()[0], 1.5) << name;
    for (std::size_t i = 0; i < image.voxel_count(); ++i) ASSERT_EQ(image.at(i), label(i)) << name;
  }
}

TEST(ImageIo, FramesAreStackedAlongTime) {
  std::vector<std::string> frames;
  for (int f = 0; f < 3; ++f) {
    frames.push_back(temp_path("frame" + std::to_string(f) + ".nii.gz"));
    write_itk<std::uint8_t, 3>(frames.back(), {4, 4, 4}, [f](std::size_t i) {
      return static_cast<std::uint8_t>(i == 21 + static_cast<std::size_t>(f) ? 1 : 0);
    });
  }
  const LabelImage4 image = read_label_frames(frames, 2.5);
  EXPECT_EQ(image.dims(), (Dims4{4, 4, 4, 3}));
  EXPECT_DOUBLE_EQ(image.spacing()[3], 2.5);
  for (std::size_t f = 0; f < 3; ++f) EXPECT_EQ(image.at(64 * f + 21 + f), 1);
  EXPECT_EQ(image.labels(), (std::vector<Label>{0, 1}));
}

TEST(ImageIo, FramesOfDifferentSizesAreRefused) {
  write_itk<std::uint8_t, 3>(temp_path("a.nii"), {4, 4, 4}, [](std::size_t) { return 1; });
  write_itk<std::uint8_t, 3>(temp_path("b.nii"), {4, 4, 5}, [](std::size_t) { return 1; });
  EXPECT_THROW(read_label_frames({temp_path("a.nii"), temp_path("b.nii")}, 1.0), ImageError);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ImageError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ImageIo, BadFilesGiveClearErrors) {
  EXPECT_NE(error_of([] { read_label_image(temp_path("missing.nii.gz")); }).find("cannot read"),
            std::string::npos);
  { std::ofstream(temp_path("garbage.nii")) << "this is not an image at all"; }
  EXPECT_NE(error_of([] { read_label_image(temp_path("garbage.nii")); }).find("garbage.nii"),
            std::string::npos);
  write_itk<float, 4>(temp_path("float.nii"), {3, 3, 3, 3}, [](std::size_t) { return 0.5f; });
  EXPECT_NE(error_of([] { read_label_image(temp_path("float.nii")); }).find("integers"),
            std::string::npos);
  write_itk<std::uint8_t, 3>(temp_path("three.nii"), {3, 3, 3}, [](std::size_t) { return 1; });
  EXPECT_NE(error_of([] { read_label_image(temp_path("three.nii")); }).find("3-dimensional"),
            std::string::npos);
  EXPECT_NE(error_of([] { write_nifti(hypersphere_phantom(), temp_path("x.png")); }).find(".nii"),
            std::string::npos);
}

// A file cut short (an interrupted copy or upload) is refused, compressed or not; ITK alone
// reads a truncated .nii.gz as if the missing voxels were background.
TEST(ImageIo, TruncatedFilesAreRefused) {
  for (const std::string name : {"cut.nii.gz", "cut.nii"}) {
    SCOPED_TRACE(name);
    write_nifti(hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 6), temp_path(name));
    std::string bytes;
    {
      std::ifstream in(temp_path(name), std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    ASSERT_NO_THROW(read_label_image(temp_path(name)));
    std::ofstream(temp_path(name), std::ios::binary | std::ios::trunc)
        << bytes.substr(0, bytes.size() * 2 / 3);
    EXPECT_THROW(read_label_image(temp_path(name)), ImageError);
  }
  EXPECT_NE(error_of([] { read_label_image(temp_path("cut.nii.gz")); }).find("truncated"),
            std::string::npos);
}

// A gzip bomb: a small .nii.gz whose header announces far more voxels than the reader may take
// (the zeros inflate 1000:1). Refused from the header, before anything is inflated or allocated:
// the old reader took the whole image into 64-bit pixels first (a 1 GiB file: 10 GB).
TEST(ImageIo, AHeaderOverTheVoxelLimitIsRefusedBeforeTheVoxelsAreRead) {
  const std::string small = temp_path("small.nii");
  write_nifti(hypersphere_phantom({8, 8, 8, 2}, {1, 1, 1, 1}, 3), small);
  std::string header;
  {
    std::ifstream in(small, std::ios::binary);
    header.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GE(header.size(), 352u);
  header.resize(352);  // the NIfTI-1 header and its 4 extension bytes: voxels start here
  const std::int16_t dims[4] = {256, 256, 128, 4};  // 32 Mi uint8 voxels
  std::memcpy(&header[42], dims, sizeof dims);
  const std::string bomb = temp_path("bomb.nii.gz");
  gzFile out = gzopen(bomb.c_str(), "wb1");
  ASSERT_NE(out, nullptr);
  gzwrite(out, header.data(), static_cast<unsigned>(header.size()));
  const std::vector<char> zeros(1 << 20, 0);
  for (int mb = 0; mb < 32; ++mb) gzwrite(out, zeros.data(), static_cast<unsigned>(zeros.size()));
  gzclose(out);
  EXPECT_LT(fs::file_size(bomb), 256u << 10);

  const auto peak_kb = [] {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
  };
  const long before = peak_kb();
  EXPECT_THROW(read_label_image(bomb, nullptr, 16u << 20), ImageTooLarge);
  EXPECT_NE(error_of([&] { read_label_image(bomb, nullptr, 16u << 20); }).find("33554432 voxels"),
            std::string::npos);
  EXPECT_LT(peak_kb() - before, 32 * 1024) << "KiB more at the peak";
  // Within the limit the same file is read.
  EXPECT_EQ(read_label_image(bomb, nullptr, 64u << 20).voxel_count(), 32u << 20);
}

// A header that asks for a few voxels followed by a stream that inflates far beyond them: only
// the voxels are inflated and read.
TEST(ImageIo, BytesPastTheVoxelsAreNotRead) {
  const auto image = hypersphere_phantom({8, 8, 8, 4}, {1, 1, 1, 1}, 3);
  const std::string plain = temp_path("tail.nii");
  write_nifti(image, plain);
  std::string bytes;
  {
    std::ifstream in(plain, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string tail = temp_path("tail.nii.gz");
  gzFile out = gzopen(tail.c_str(), "wb1");
  gzwrite(out, bytes.data(), static_cast<unsigned>(bytes.size()));
  // Then a stream that is not even valid past the first megabytes: never reached.
  const std::vector<char> zeros(1 << 20, 0);
  for (int mb = 0; mb < 8; ++mb) gzwrite(out, zeros.data(), static_cast<unsigned>(zeros.size()));
  gzclose(out);
  std::string gz;
  {
    std::ifstream in(tail, std::ios::binary);
    gz.assign(std::istreambuf_iterator<char>(in), {});
  }
  gz.resize(gz.size() - 64);  // cut inside the trailing zeros' compressed data
  std::ofstream(tail, std::ios::binary | std::ios::trunc) << gz;
  expect_same(read_label_image(tail), image);
}

// The paper's patients (../shared/data/heart4d/README.md): dims, in-plane spacing, labels 0-2.
TEST(HeartData, FivePatientsLoadWithTheirDimsSpacingAndLabels) {
  const fs::path dir = MESH4D_HEART_DATA_DIR;
  if (!fs::exists(dir)) GTEST_SKIP() << "no real data: " << dir << " is absent";
  struct Expected {
    const char* file;
    std::size_t z;
    double mm;
  };
  const Expected patients[] = {{"Pat01_mse4d_label4d.nii.gz", 44, 1.77},
                               {"Pat02_mse4d_label4d.nii.gz", 34, 1.77},
                               {"Pat03_mse4d_label4d.nii.gz", 26, 2.08},
                               {"Pat04_mse4d_label4d.nii.gz", 31, 1.77},
                               {"Pat05_mse4d_label4d.nii.gz", 29, 1.88}};
  for (const auto& p : patients) {
    const LabelImage4 image = read_label_image((dir / p.file).string());
    EXPECT_EQ(image.dims(), (Dims4{100, 100, p.z, 25})) << p.file;
    EXPECT_NEAR(image.spacing()[0], p.mm, 0.01) << p.file;
    EXPECT_NEAR(image.spacing()[1], p.mm, 0.01) << p.file;
    EXPECT_NEAR(image.spacing()[3], 1.0, 1e-9) << p.file;
    EXPECT_EQ(image.labels(), (std::vector<Label>{0, 1, 2})) << p.file;
  }
}

}  // namespace
}  // namespace mesh4d::domain
