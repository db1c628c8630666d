#include "wire/upload_codec.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "domain/time_extension.h"
#include "wire/digest.h"
#include "wire/service_error.h"

namespace mesh4d::wire {
namespace {

[[noreturn]] void bad(const std::string& message) {
  throw ServiceError(ErrorCode::invalid_argument, message);
}

domain::LabelType engine_type(v1::LabelType type) {
  switch (type) {
    case v1::LABEL_TYPE_UINT8:
      return domain::LabelType::uint8;
    case v1::LABEL_TYPE_UINT16:
      return domain::LabelType::uint16;
    case v1::LABEL_TYPE_INT16:
      return domain::LabelType::int16;
    default:
      bad("image.label_type must be UINT8, UINT16 or INT16");
  }
}

}  // namespace

std::string encode_upload(const domain::LabelImage4& image, v1::ImageHeader* h) {
  const auto labels = image.labels();
  const bool wide = !labels.empty() && labels.back() > 255;
  std::string raw(image.voxel_count() * (wide ? 2 : 1), '\0');
  for (std::size_t i = 0; i < image.voxel_count(); ++i) {
    const auto l = image.at(i);
    if (wide) {
      raw[2 * i] = static_cast<char>(l & 0xFF);
      raw[2 * i + 1] = static_cast<char>(l >> 8);
    } else {
      raw[i] = static_cast<char>(l);
    }
  }
  const auto& d = image.dims();
  h->mutable_dims()->set_x(d[0]), h->mutable_dims()->set_y(d[1]);
  h->mutable_dims()->set_z(d[2]), h->mutable_dims()->set_t(d[3]);
  const auto& s = image.spacing();
  h->mutable_spacing()->set_x(s[0]), h->mutable_spacing()->set_y(s[1]);
  h->mutable_spacing()->set_z(s[2]), h->mutable_spacing()->set_t(s[3]);
  const auto& org = image.origin();
  h->mutable_origin()->set_x(org[0]), h->mutable_origin()->set_y(org[1]);
  h->mutable_origin()->set_z(org[2]), h->mutable_origin()->set_t(org[3]);
  h->set_label_type(wide ? v1::LABEL_TYPE_UINT16 : v1::LABEL_TYPE_UINT8);
  h->set_byte_size(raw.size());
  h->set_sha256(sha256(raw));
  return raw;
}

std::size_t label_bytes(v1::LabelType type) {
  return engine_type(type) == domain::LabelType::uint8 ? 1 : 2;
}

std::uint64_t check_header(const v1::ImageHeader& h) {
  if (!h.has_dims()) bad("image.dims is missing");
  const std::uint64_t d[4] = {h.dims().x(), h.dims().y(), h.dims().z(), h.dims().t()};
  std::uint64_t voxels = 1;
  for (int a = 0; a < 4; ++a) {
    if (d[a] == 0) bad("image.dims must all be positive (a 4D image: x, y, z, t)");
    if (voxels > std::numeric_limits<std::uint64_t>::max() / d[a] / 2)
      throw ServiceError(ErrorCode::resource_exhausted, "image.dims are absurdly large");
    voxels *= d[a];
  }
  const double s[4] = {h.spacing().x(), h.spacing().y(), h.spacing().z(), h.spacing().t()};
  const double o[4] = {h.origin().x(), h.origin().y(), h.origin().z(), h.origin().t()};
  static const char* axis[4] = {"x", "y", "z", "t"};
  for (int a = 0; a < 4; ++a) {
    if (!std::isfinite(s[a]) || s[a] <= 0)
      bad(std::string("image.spacing.") + axis[a] + " must be finite and positive");
    if (!std::isfinite(o[a])) bad(std::string("image.origin.") + axis[a] + " must be finite");
  }
  const std::uint64_t expected = voxels * label_bytes(h.label_type());
  if (h.byte_size() != expected) {
    std::ostringstream m;
    m << "image.byte_size is " << h.byte_size() << " but dims " << d[0] << "x" << d[1] << "x"
      << d[2] << "x" << d[3] << " of " << label_bytes(h.label_type()) << "-byte labels make "
      << expected;
    bad(m.str());
  }
  if (h.sha256().size() != 32) bad("image.sha256 must be the 32-byte SHA-256 of the data");
  return expected;
}

namespace {

// The checked data as an image, with its end frames repeated; closed (and its labels checked)
// when `close`.
domain::LabelImage4 decode(const v1::ImageHeader& h, std::string_view data,
                           std::size_t extend_time_frames, bool close,
                           std::vector<std::string>* warnings) {
  const std::uint64_t expected = check_header(h);
  if (data.size() != expected) {
    std::ostringstream m;
    m << "received " << data.size() << " bytes of label data, the header announced " << expected;
    bad(m.str());
  }
  if (sha256(data) != h.sha256())
    bad("the label data does not match image.sha256 (corrupted upload?)");
  try {
    auto image = domain::LabelImage4::from_raw(
        {h.dims().x(), h.dims().y(), h.dims().z(), h.dims().t()},
        {h.spacing().x(), h.spacing().y(), h.spacing().z(), h.spacing().t()},
        {h.origin().x(), h.origin().y(), h.origin().z(), h.origin().t()},
        engine_type(h.label_type()), data.data(), data.size());
    if (extend_time_frames > 0) image = domain::extend_time(image, extend_time_frames);
    std::vector<std::string> w;
    if (close) w = domain::validate_and_close(image);
    if (extend_time_frames > 0) {
      std::ostringstream m;
      m << "the first and last frames were repeated " << extend_time_frames
        << " times (extend_time_frames): the mesh spans that many more frames at each end";
      w.push_back(m.str());
    }
    if (warnings) *warnings = std::move(w);
    return image;
  } catch (const domain::ImageError& e) {
    bad(e.what());
  }
}

}  // namespace

domain::LabelImage4 decode_upload(const v1::ImageHeader& h, std::string_view data,
                                  std::vector<std::string>* warnings,
                                  std::size_t extend_time_frames) {
  return decode(h, data, extend_time_frames, true, warnings);
}

domain::LabelImage4 decode_unclosed(const v1::ImageHeader& h, std::string_view data,
                                    std::vector<std::string>* warnings,
                                    std::size_t extend_time_frames) {
  return decode(h, data, extend_time_frames, false, warnings);
}

}  // namespace mesh4d::wire
