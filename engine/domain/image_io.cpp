// ITK stays in this translation unit: the rest of the engine sees only LabelImage4.
#include "domain/image_io.h"

#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkImageIOFactory.h>
#include <itkMetaImageIOFactory.h>
#include <itkNiftiImageIOFactory.h>
#include <itkNrrdImageIOFactory.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <mutex>
#include <sstream>

#include "domain/nrrd_data_check.h"

namespace mesh4d::domain {

// The three formats mesh4d reads, registered explicitly (not through ITK's CMake-generated
// registration), so that reading does not depend on how the executable was configured.
void register_image_formats() {
  static std::once_flag once;
  std::call_once(once, [] {
    itk::NiftiImageIOFactory::RegisterOneFactory();
    itk::MetaImageIOFactory::RegisterOneFactory();
    itk::NrrdImageIOFactory::RegisterOneFactory();
  });
}

namespace {

bool is_integer_component(itk::IOComponentEnum c) {
  using C = itk::IOComponentEnum;
  return c == C::UCHAR || c == C::CHAR || c == C::USHORT || c == C::SHORT || c == C::UINT ||
         c == C::INT || c == C::ULONG || c == C::LONG || c == C::ULONGLONG || c == C::LONGLONG;
}

// What mesh4d checks in a NIfTI header before ITK reads it. sizeof_hdr says the version and,
// read swapped, the byte order: NIfTI-1 (348) has dim as int16[8] at 40, pixdim as float[8] at
// 76, vox_offset as a float at 108, the quaternion and its offset as 6 floats at 256 and the
// affine rows as 12 floats at 280; NIfTI-2 (540) has dim as int64[8] at 16, pixdim as double[8]
// at 104, vox_offset as an int64 at 168, then the same 6 + 12 numbers as doubles at 352.
using NiftiHeader = std::array<unsigned char, 540>;

struct NiftiFacts {
  double voxel_offset = -1;  // -1: not a NIfTI header
  int dims = 0;
  std::array<double, 4> spacing{};  // pixdim[1..4]
  // ITK builds the direction matrix from pixdim[0], the quaternion and the affine rows by an
  // SVD in single precision: a non-finite entry makes it call abort(), and one near the float
  // range (1e38) makes it loop for ever. Either way one upload would end or hang the server.
  bool orientation_sane = true;
};

// An orientation number that a medical image can have: a unit quaternion's part, a direction
// times a voxel size, or an offset, in mm: at most a kilometre.
bool sane_orientation_number(double x) {
  return std::isfinite(x) && std::abs(x) <= 1e6;
}

NiftiFacts read_nifti_facts(const NiftiHeader& header) {
  const auto read = [&](std::size_t at, std::size_t bytes, bool swap) {
    std::array<unsigned char, 8> b{};
    for (std::size_t k = 0; k < bytes; ++k) b[k] = header[at + (swap ? bytes - 1 - k : k)];
    return b;
  };
  std::int32_t sizeof_hdr = 0;
  bool swap = false;
  for (bool s : {false, true}) {
    std::memcpy(&sizeof_hdr, read(0, 4, s).data(), 4);
    if (sizeof_hdr == 348 || sizeof_hdr == 540) {
      swap = s;
      break;
    }
  }
  NiftiFacts facts;
  if (sizeof_hdr == 348) {
    float f32;
    std::memcpy(&f32, read(108, 4, swap).data(), 4);
    facts.voxel_offset = f32;
    std::int16_t i16;
    std::memcpy(&i16, read(40, 2, swap).data(), 2);
    facts.dims = i16;
    for (int a = 0; a < 4; ++a) {
      std::memcpy(&f32, read(80 + 4 * a, 4, swap).data(), 4);
      facts.spacing[a] = f32;
    }
    for (std::size_t at : {76, 256, 260, 264, 268, 272, 276, 280, 284, 288, 292, 296, 300, 304, 308,
                           312, 316, 320, 324}) {
      std::memcpy(&f32, read(at, 4, swap).data(), 4);
      facts.orientation_sane = facts.orientation_sane && sane_orientation_number(f32);
    }
  } else if (sizeof_hdr == 540) {
    std::int64_t i64;
    std::memcpy(&i64, read(168, 8, swap).data(), 8);
    facts.voxel_offset = static_cast<double>(i64);
    std::memcpy(&i64, read(16, 8, swap).data(), 8);
    facts.dims = i64 >= 1 && i64 <= 7 ? static_cast<int>(i64) : -1;
    for (int a = 0; a < 4; ++a) {
      double f64;
      std::memcpy(&f64, read(112 + 8 * a, 8, swap).data(), 8);
      facts.spacing[a] = f64;
    }
    for (std::size_t at = 352; at < 496; at += 8) {
      double f64;
      std::memcpy(&f64, read(at, 8, swap).data(), 8);
      facts.orientation_sane = facts.orientation_sane && sane_orientation_number(f64);
    }
    double pixdim0;
    std::memcpy(&pixdim0, read(104, 8, swap).data(), 8);
    facts.orientation_sane = facts.orientation_sane && sane_orientation_number(pixdim0);
  }
  return facts;
}

// ITK reads a voxel size of 0 or NaN as 1, and a negative one as its absolute value: a header
// that says so is refused, as the gRPC face refuses such a spacing.
void check_nifti_spacing(const std::string& path, const NiftiFacts& facts) {
  if (!facts.orientation_sane)
    throw ImageError(path +
                     ": the header's orientation (pixdim[0], the quaternion or the affine "
                     "rows) holds a number that is not finite or is beyond 1e6");
  static const char* axis[4] = {"x", "y", "z", "t"};
  for (int a = 0; a < std::min(facts.dims, 4); ++a)
    if (!std::isfinite(facts.spacing[a]) || facts.spacing[a] <= 0) {
      std::ostringstream m;
      m << path << ": the header's voxel size along " << axis[a] << " (pixdim[" << a + 1 << "]) is "
        << facts.spacing[a] << "; it must be a finite positive number";
      throw ImageError(m.str());
    }
}

// The NIfTI header's numbers that ITK would take in silently or die on, checked before ITK reads
// the header (its first 540 bytes, inflated no further).
void check_nifti_header(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) return;  // missing or unreadable: the reader says so
  NiftiHeader header{};
  const int n = gzread(f, header.data(), static_cast<unsigned>(header.size()));
  gzclose_r(f);
  if (n <= 0) return;
  const NiftiFacts facts = read_nifti_facts(header);
  // ITK's NIfTI library takes a header by its magic alone and its byte order from dim[0]; the
  // checks here read it by sizeof_hdr. A file that ITK's NIfTI reader is given must satisfy both.
  if (facts.voxel_offset < 0 || facts.dims < 1 || facts.dims > 7)
    throw ImageError(path +
                     ": not a NIfTI header: sizeof_hdr (348 or 540) and dim[0] (1 to 7) "
                     "do not agree on a version and byte order");
  check_nifti_spacing(path, facts);
}

// ITK's NIfTI reader takes a file that ends early, compressed or not, for a whole one (the
// missing voxels read as zeros): the stream (zlib reads plain files too) must hold the header's
// voxel offset plus every voxel. It is inflated only that far: a small file can inflate to
// gigabytes, and what lies past the voxels is never read.
void check_nifti_complete(const std::string& path, std::uint64_t voxel_bytes) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) return;  // missing or unreadable: the reader says so
  std::vector<char> buffer(1 << 16);
  NiftiHeader header{};
  std::uint64_t total = 0;
  double needed = -1;  // once the header is in: its voxel offset plus the voxels
  int n = 0;
  while ((needed < 0 || double(total) < needed) &&
         (n = gzread(f, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0) {
    for (std::size_t i = 0; i < static_cast<std::size_t>(n) && total + i < header.size(); ++i)
      header[total + i] = static_cast<unsigned char>(buffer[i]);
    total += static_cast<std::uint64_t>(n);
    if (needed < 0 && total >= header.size()) {
      const NiftiFacts facts = read_nifti_facts(header);
      if (facts.voxel_offset < 0) break;  // not a NIfTI header: ITK will say what it is
      needed = facts.voxel_offset + double(voxel_bytes);
    }
  }
  int code = Z_OK;
  const std::string error = n < 0 ? gzerror(f, &code) : "";
  const int closed = gzclose_r(f);
  if (n < 0) throw ImageError(path + ": the compressed data is corrupt (" + error + ")");
  if (needed < 0 && total < header.size()) {  // shorter than a header
    needed = read_nifti_facts(header).voxel_offset;
    if (needed >= 0) needed += double(voxel_bytes);
  }
  if (needed < 0 || double(total) >= needed) return;  // not a NIfTI file, or complete
  if (closed == Z_BUF_ERROR)
    throw ImageError(path + ": the compressed file is truncated (it ends inside the data)");
  throw ImageError(path + ": the file is truncated: " + std::to_string(total) +
                   " bytes hold less than the header's " + std::to_string(voxel_bytes) +
                   " bytes of voxels");
}

// Opens the file's header and checks what can be checked before reading voxels.
itk::ImageIOBase::Pointer open_header(const std::string& path, unsigned expected_dims_min,
                                      unsigned expected_dims_max, std::uint64_t max_voxels = 0) {
  register_image_formats();
  itk::ImageIOBase::Pointer io =
      itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::ReadMode);
  if (!io)
    throw ImageError(path +
                     ": cannot read: missing, unreadable, or not a NIfTI, MetaImage or "
                     "NRRD file");
  const auto ends_with = [&](const char* suffix) {
    const std::string x = suffix;
    return path.size() > x.size() && path.compare(path.size() - x.size(), x.size(), x) == 0;
  };
  if (ends_with(".nii") || ends_with(".nii.gz")) check_nifti_header(path);
  try {
    io->SetFileName(path);
    io->ReadImageInformation();
  } catch (const itk::ExceptionObject& e) {
    throw ImageError(path + ": cannot read the header: " + e.GetDescription());
  }
  // The size first, from the header alone: nothing is inflated or allocated for an image that
  // is over the limit, or whose dimensions overflow.
  std::uint64_t voxels = 1;
  for (unsigned a = 0; a < io->GetNumberOfDimensions(); ++a) {
    const std::uint64_t d = io->GetDimensions(a);
    if (d == 0) throw ImageError(path + ": the header gives a dimension of 0 voxels");
    if (voxels > (std::uint64_t{1} << 62) / d)
      throw ImageTooLarge(path + ": the header's dimensions are absurdly large");
    voxels *= d;
  }
  if (max_voxels > 0 && voxels > max_voxels)
    throw ImageTooLarge(path + ": the header announces " + std::to_string(voxels) +
                        " voxels; at most " + std::to_string(max_voxels) + " are accepted");
  if (ends_with(".nii") || ends_with(".nii.gz"))
    check_nifti_complete(path, io->GetImageSizeInBytes());
  if (ends_with(".nrrd")) check_nrrd_data_complete(path, io->GetImageSizeInBytes());
  const unsigned n = io->GetNumberOfDimensions();
  if (n < expected_dims_min || n > expected_dims_max) {
    std::ostringstream s;
    s << path << ": image is " << n << "-dimensional; ";
    if (expected_dims_min == 4)
      s << "a 4D image (x, y, z, t) is needed, or one 3D file per frame";
    else
      s << "each frame must be a 3D image";
    throw ImageError(s.str());
  }
  if (io->GetNumberOfComponents() != 1)
    throw ImageError(path + ": pixels have " + std::to_string(io->GetNumberOfComponents()) +
                     " components; a label image has one");
  if (!is_integer_component(io->GetComponentType()))
    throw ImageError(path + ": pixels are " +
                     itk::ImageIOBase::GetComponentTypeAsString(io->GetComponentType()) +
                     "; a label image holds integers (uint8, uint16 or int16)");
  return io;
}

using ReadImage = itk::Image<std::int64_t, 4>;

ReadImage::Pointer read_voxels(const std::string& path) {
  auto reader = itk::ImageFileReader<ReadImage>::New();
  reader->SetFileName(path);
  try {
    reader->Update();
  } catch (const itk::ExceptionObject& e) {
    throw ImageError(path + ": cannot read the voxels: " + e.GetDescription());
  }
  return reader->GetOutput();
}

Label checked_label(std::int64_t v, const std::string& path) {
  if (v < 0 || v > 65535) {
    std::ostringstream s;
    s << path << ": label " << v << " is out of range; labels must be in 0..65535";
    throw ImageError(s.str());
  }
  return static_cast<Label>(v);
}

void note_direction(const ReadImage* image, const std::string& path,
                    std::vector<std::string>* warnings) {
  const auto& dir = image->GetDirection();
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c)
      if (std::abs(dir[r][c] - (r == c ? 1.0 : 0.0)) > 1e-6) {
        if (warnings)
          warnings->push_back(path +
                              ": direction cosines are not the identity; they are "
                              "ignored and the axes taken as x, y, z, t");
        return;
      }
}

}  // namespace

LabelImage4 read_label_image(const std::string& path, std::vector<std::string>* warnings,
                             std::uint64_t max_voxels) {
  open_header(path, 4, 4, max_voxels);
  const ReadImage::Pointer image = read_voxels(path);
  const auto size = image->GetLargestPossibleRegion().GetSize();
  const auto spacing = image->GetSpacing();
  const auto origin = image->GetOrigin();
  note_direction(image, path, warnings);
  LabelImage4 out({size[0], size[1], size[2], size[3]},
                  {spacing[0], spacing[1], spacing[2], spacing[3]},
                  {origin[0], origin[1], origin[2], origin[3]});
  const std::int64_t* buffer = image->GetBufferPointer();
  for (std::size_t i = 0; i < out.voxel_count(); ++i)
    if (buffer[i] != 0) out.set(i, checked_label(buffer[i], path));
  return out;
}

LabelImage4 read_label_frames(const std::vector<std::string>& paths, double time_scale,
                              std::vector<std::string>* warnings) {
  if (paths.empty()) throw ImageError("no frame files given");
  std::vector<ReadImage::Pointer> frames;
  for (const auto& path : paths) {
    const auto io = open_header(path, 3, 4);
    if (io->GetNumberOfDimensions() == 4 && io->GetDimensions(3) != 1)
      throw ImageError(path + ": a frame must be a 3D image, this one has " +
                       std::to_string(io->GetDimensions(3)) + " time points");
    frames.push_back(read_voxels(path));
  }
  const auto size = frames[0]->GetLargestPossibleRegion().GetSize();
  const auto spacing = frames[0]->GetSpacing();
  const auto origin = frames[0]->GetOrigin();
  for (std::size_t f = 1; f < frames.size(); ++f) {
    const auto s = frames[f]->GetLargestPossibleRegion().GetSize();
    const auto sp = frames[f]->GetSpacing();
    for (int a = 0; a < 3; ++a) {
      if (s[a] != size[a])
        throw ImageError(paths[f] + ": frame size differs from the first frame's (" + paths[0] +
                         ")");
      if (std::abs(sp[a] - spacing[a]) > 1e-9 * spacing[a])
        throw ImageError(paths[f] + ": frame spacing differs from the first frame's");
    }
  }
  note_direction(frames[0], paths[0], warnings);
  LabelImage4 out({size[0], size[1], size[2], frames.size()},
                  {spacing[0], spacing[1], spacing[2], time_scale},
                  {origin[0], origin[1], origin[2], 0.0});
  const std::size_t per_frame = size[0] * size[1] * size[2];
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const std::int64_t* buffer = frames[f]->GetBufferPointer();
    for (std::size_t i = 0; i < per_frame; ++i)
      if (buffer[i] != 0) out.set(f * per_frame + i, checked_label(buffer[i], paths[f]));
  }
  return out;
}

namespace {

template <class Pixel>
void write_as(const LabelImage4& image, const std::string& path) {
  using Image = itk::Image<Pixel, 4>;
  auto out = Image::New();
  typename Image::SizeType size;
  typename Image::SpacingType spacing;
  typename Image::PointType origin;
  for (unsigned a = 0; a < 4; ++a) {
    size[a] = image.dims()[a];
    spacing[a] = image.spacing()[a];
    origin[a] = image.origin()[a];
  }
  out->SetRegions(typename Image::RegionType(size));
  out->SetSpacing(spacing);
  out->SetOrigin(origin);
  out->Allocate();
  Pixel* buffer = out->GetBufferPointer();
  for (std::size_t i = 0; i < image.voxel_count(); ++i) buffer[i] = static_cast<Pixel>(image.at(i));
  auto writer = itk::ImageFileWriter<Image>::New();
  writer->SetFileName(path);
  writer->SetInput(out);
  writer->SetUseCompression(true);
  try {
    writer->Update();
  } catch (const itk::ExceptionObject& e) {
    throw ImageError(path + ": cannot write: " + e.GetDescription());
  }
}

}  // namespace

void write_nifti(const LabelImage4& image, const std::string& path) {
  register_image_formats();
  const bool nifti = path.ends_with(".nii") || path.ends_with(".nii.gz");
  if (!nifti) throw ImageError(path + ": a NIfTI file name ends in .nii or .nii.gz");
  if (image.storage_bytes() == image.voxel_count())
    write_as<std::uint8_t>(image, path);
  else
    write_as<std::uint16_t>(image, path);
}

}  // namespace mesh4d::domain
