#include "domain/label_image.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace mesh4d::domain {
namespace {

const char* const kAxisNames[4] = {"x", "y", "z", "t"};

void check_geometry(const Dims4& dims, const Vec4& spacing, const Vec4& origin) {
  for (int a = 0; a < 4; ++a) {
    if (dims[a] == 0)
      throw ImageError(std::string("image is empty: size along ") + kAxisNames[a] + " is 0");
    if (!std::isfinite(spacing[a]) || spacing[a] <= 0) {
      std::ostringstream s;
      s << "spacing along " << kAxisNames[a] << " must be finite and positive, got " << spacing[a];
      throw ImageError(s.str());
    }
    if (!std::isfinite(origin[a])) {
      std::ostringstream s;
      s << "origin along " << kAxisNames[a] << " must be finite, got " << origin[a];
      throw ImageError(s.str());
    }
  }
  // Indices are 32-bit in the feature transform; keep a margin for padding.
  const double voxels = double(dims[0]) * double(dims[1]) * double(dims[2]) * double(dims[3]);
  if (voxels > 4.0e9) throw ImageError("image has more than 4·10⁹ voxels");
}

}  // namespace

std::size_t bytes_per_label(LabelType type) {
  return type == LabelType::uint8 ? 1 : 2;
}

LabelImage4::LabelImage4(const Dims4& dims, const Vec4& spacing, const Vec4& origin)
    : dims_(dims), spacing_(spacing), origin_(origin) {
  check_geometry(dims, spacing, origin);
  narrow_labels_.assign(voxel_count(), 0);
}

void LabelImage4::set_time_spacing(double spacing) {
  Vec4 spacing4 = spacing_, origin = origin_;
  spacing4[3] = spacing;
  origin[3] = origin_[3] / spacing_[3] * spacing;
  check_geometry(dims_, spacing4, origin);
  spacing_ = spacing4;
  origin_ = origin;
}

LabelImage4 LabelImage4::from_raw(const Dims4& dims, const Vec4& spacing, const Vec4& origin,
                                  LabelType type, const void* data, std::size_t bytes) {
  LabelImage4 image(dims, spacing, origin);
  const std::size_t expected = image.voxel_count() * bytes_per_label(type);
  if (bytes != expected) {
    std::ostringstream s;
    s << "label data has " << bytes << " bytes, but " << dims[0] << "×" << dims[1] << "×" << dims[2]
      << "×" << dims[3] << " voxels of " << bytes_per_label(type) << " byte(s) need " << expected;
    throw ImageError(s.str());
  }
  const auto* b = static_cast<const unsigned char*>(data);
  const std::size_t n = image.voxel_count();
  for (std::size_t i = 0; i < n; ++i) {
    Label value = 0;
    if (type == LabelType::uint8) {
      value = b[i];
    } else {
      const std::uint16_t raw = static_cast<std::uint16_t>(b[2 * i] | (b[2 * i + 1] << 8));
      if (type == LabelType::int16 && (raw & 0x8000u)) {
        std::ostringstream s;
        s << "negative label " << static_cast<std::int16_t>(raw) << " at voxel " << i
          << ": labels must be 0 (background) or positive";
        throw ImageError(s.str());
      }
      value = raw;
    }
    if (value != 0) image.set(i, value);
  }
  return image;
}

void LabelImage4::set(std::size_t i, Label label) {
  if (!wide_ && label > 255) {
    wide_labels_.assign(narrow_labels_.begin(), narrow_labels_.end());
    narrow_labels_.clear();
    narrow_labels_.shrink_to_fit();
    wide_ = true;
  }
  if (wide_)
    wide_labels_[i] = label;
  else
    narrow_labels_[i] = static_cast<std::uint8_t>(label);
}

Point4 LabelImage4::voxel_center(std::size_t x, std::size_t y, std::size_t z, std::size_t t) const {
  return {origin_[0] + double(x) * spacing_[0], origin_[1] + double(y) * spacing_[1],
          origin_[2] + double(z) * spacing_[2], origin_[3] + double(t) * spacing_[3]};
}

std::array<Point4, 2> LabelImage4::bounds() const {
  return {voxel_center(0, 0, 0, 0),
          voxel_center(dims_[0] - 1, dims_[1] - 1, dims_[2] - 1, dims_[3] - 1)};
}

std::vector<Label> LabelImage4::labels() const {
  std::vector<bool> seen(wide_ ? 65536 : 256, false);
  const std::size_t n = voxel_count();
  for (std::size_t i = 0; i < n; ++i) seen[at(i)] = true;
  std::vector<Label> out;
  for (std::size_t v = 0; v < seen.size(); ++v)
    if (seen[v]) out.push_back(static_cast<Label>(v));
  return out;
}

std::size_t LabelImage4::storage_bytes() const {
  return wide_ ? wide_labels_.size() * 2 : narrow_labels_.size();
}

std::vector<std::string> validate_and_close(LabelImage4& image) {
  const std::vector<Label> labels = image.labels();
  const std::size_t foreground = labels.size() - (labels.front() == 0 ? 1 : 0);
  if (foreground == 0) throw ImageError("image has no foreground: every voxel is label 0");
  if (foreground > kMaxLabels) {
    std::ostringstream s;
    s << "image has " << foreground << " distinct labels; at most " << kMaxLabels
      << " are supported (is this an intensity image rather than a segmentation?)";
    throw ImageError(s.str());
  }

  // Which sides does the foreground touch? pad[a][0] low side, pad[a][1] high side.
  const Dims4 d = image.dims();
  bool pad[4][2] = {};
  for (std::size_t t = 0; t < d[3]; ++t)
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x) {
          if (image.at(x, y, z, t) == 0) continue;
          const std::size_t c[4] = {x, y, z, t};
          for (int a = 0; a < 4; ++a) {
            if (c[a] == 0) pad[a][0] = true;
            if (c[a] == d[a] - 1) pad[a][1] = true;
          }
        }
  std::vector<std::string> warnings;
  Dims4 nd = d;
  Vec4 origin = image.origin();
  std::size_t shift[4] = {0, 0, 0, 0};
  for (int a = 0; a < 4; ++a) {
    if (!pad[a][0] && !pad[a][1]) continue;
    nd[a] += (pad[a][0] ? 1 : 0) + (pad[a][1] ? 1 : 0);
    if (pad[a][0]) {
      shift[a] = 1;
      origin[a] -= image.spacing()[a];
    }
    std::ostringstream s;
    s << "the object touches the image border along " << kAxisNames[a]
      << "; padded with one background voxel on the "
      << (pad[a][0] && pad[a][1] ? "low and high sides"
          : pad[a][0]            ? "low side"
                                 : "high side")
      << " to close it";
    warnings.push_back(s.str());
  }
  if (warnings.empty()) return warnings;

  LabelImage4 padded(nd, image.spacing(), origin);
  for (std::size_t t = 0; t < d[3]; ++t)
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x) {
          const Label l = image.at(x, y, z, t);
          if (l != 0) padded.set(x + shift[0], y + shift[1], z + shift[2], t + shift[3], l);
        }
  image = std::move(padded);
  return warnings;
}

}  // namespace mesh4d::domain
