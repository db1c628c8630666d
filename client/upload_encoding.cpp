#include "upload_encoding.h"

#include "mesh/mesh_io.h"

namespace mesh4d::client {

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
  const auto digest = mesh::sha256(reinterpret_cast<const std::uint8_t*>(raw.data()), raw.size());
  h->set_sha256(std::string(reinterpret_cast<const char*>(digest.data()), digest.size()));
  return raw;
}

}  // namespace mesh4d::client
