#include "upload_check.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "domain/time_extension.h"
#include "mesh/mesh_io.h"
#include "service_error.h"

namespace mesh4d::server {
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

domain::LabelImage4 decode_upload(const v1::ImageHeader& h, std::string_view data,
                                  std::vector<std::string>* warnings,
                                  std::size_t extend_time_frames) {
  const std::uint64_t expected = check_header(h);
  if (data.size() != expected) {
    std::ostringstream m;
    m << "received " << data.size() << " bytes of label data, the header announced " << expected;
    bad(m.str());
  }
  const auto digest = mesh::sha256(reinterpret_cast<const std::uint8_t*>(data.data()), data.size());
  if (std::string_view(reinterpret_cast<const char*>(digest.data()), digest.size()) != h.sha256())
    bad("the label data does not match image.sha256 (corrupted upload?)");
  try {
    auto image = domain::LabelImage4::from_raw(
        {h.dims().x(), h.dims().y(), h.dims().z(), h.dims().t()},
        {h.spacing().x(), h.spacing().y(), h.spacing().z(), h.spacing().t()},
        {h.origin().x(), h.origin().y(), h.origin().z(), h.origin().t()},
        engine_type(h.label_type()), data.data(), data.size());
    if (extend_time_frames > 0) image = domain::extend_time(image, extend_time_frames);
    auto w = domain::validate_and_close(image);
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

}  // namespace mesh4d::server
