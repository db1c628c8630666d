// A 4D label image: the meshing input. Labels are small integers (0 = background, every other
// value a tissue), stored in one byte per voxel when they fit and in two otherwise.
//
// Geometry: voxel (i, j, k, l) has its center at origin + (i·sx, j·sy, k·sz, l·st) in physical
// units; st is the time scale (physical units per frame). Direction cosines are not modelled:
// axes are aligned with x, y, z, t. Everything outside this class works in physical coordinates.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "delaunay/point4.h"

namespace mesh4d::domain {

using Label = std::uint16_t;
using Dims4 = std::array<std::size_t, 4>;
using Vec4 = std::array<double, 4>;

/// How label data are laid out in a raw upload (x fastest, then y, z, t; little-endian).
enum class LabelType { uint8, uint16, int16 };

std::size_t bytes_per_label(LabelType type);

/// Bad input image: the message says what is wrong in terms a user can act on.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// At most this many distinct non-background labels (each label is a meshed region; more is
/// almost surely an intensity image passed by mistake).
inline constexpr std::size_t kMaxLabels = 255;

class LabelImage4 {
 public:
  /// A background-filled image. Throws ImageError for a zero dimension or bad spacing/origin.
  LabelImage4(const Dims4& dims, const Vec4& spacing, const Vec4& origin = {0, 0, 0, 0});

  /// Decodes raw little-endian label data (the service's upload format). Throws ImageError when
  /// the byte count does not match dims × label size or an int16 label is negative.
  static LabelImage4 from_raw(const Dims4& dims, const Vec4& spacing, const Vec4& origin,
                              LabelType type, const void* data, std::size_t bytes);

  const Dims4& dims() const { return dims_; }
  const Vec4& spacing() const { return spacing_; }
  const Vec4& origin() const { return origin_; }
  std::size_t voxel_count() const { return dims_[0] * dims_[1] * dims_[2] * dims_[3]; }

  std::size_t linear_index(std::size_t x, std::size_t y, std::size_t z, std::size_t t) const {
    return x + dims_[0] * (y + dims_[1] * (z + dims_[2] * t));
  }
  Label at(std::size_t i) const { return wide_ ? wide_labels_[i] : narrow_labels_[i]; }
  Label at(std::size_t x, std::size_t y, std::size_t z, std::size_t t) const {
    return at(linear_index(x, y, z, t));
  }
  void set(std::size_t i, Label label);
  void set(std::size_t x, std::size_t y, std::size_t z, std::size_t t, Label label) {
    set(linear_index(x, y, z, t), label);
  }

  /// Physical center of a voxel.
  Point4 voxel_center(std::size_t x, std::size_t y, std::size_t z, std::size_t t) const;
  /// Continuous voxel coordinates of a physical point (voxel centers are integers).
  Vec4 to_index(const Point4& p) const {
    return {(p[0] - origin_[0]) / spacing_[0], (p[1] - origin_[1]) / spacing_[1],
            (p[2] - origin_[2]) / spacing_[2], (p[3] - origin_[3]) / spacing_[3]};
  }
  /// Physical bounding box of the voxel centers: {min corner, max corner}.
  std::array<Point4, 2> bounds() const;
  /// Makes `spacing` the time scale, the origin keeping its place in frames (domain/time_scale.h).
  /// Throws ImageError for a spacing that is not finite and positive.
  void set_time_spacing(double spacing);

  /// Sorted distinct labels present, background included if present.
  std::vector<Label> labels() const;
  /// Bytes of label storage (1 or 2 per voxel).
  std::size_t storage_bytes() const;

 private:
  Dims4 dims_;
  Vec4 spacing_;
  Vec4 origin_;
  bool wide_ = false;  // labels above 255 switch the storage to two bytes per voxel
  std::vector<std::uint8_t> narrow_labels_;
  std::vector<std::uint16_t> wide_labels_;
};

/// Checks that the image can be meshed and closes it: throws ImageError when there is no
/// foreground or more than kMaxLabels labels; pads with one background voxel on every side along
/// which a label touches the border (the object must be closed for its boundary to be a closed
/// hyper-surface), and returns a warning per padded axis. The origin moves so that physical
/// positions of the original voxels do not change.
std::vector<std::string> validate_and_close(LabelImage4& image);

}  // namespace mesh4d::domain
