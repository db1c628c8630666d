// The upload codec (proto/wire/upload_codec.h): what the client encodes the server decodes to
// the same image, and every header field that is wrong is named.
#include "wire/upload_codec.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "domain/label_image.h"
#include "domain/phantoms.h"
#include "wire/digest.h"
#include "wire/service_error.h"

namespace mesh4d::wire {
namespace {

// Two labels in a pattern inside a background border (a border voxel would be padded).
domain::LabelImage4 two_labels(domain::Label second) {
  domain::LabelImage4 image({8, 7, 6, 5}, {1.5, 1, 2, 3}, {-4, 0, 1, 10});
  for (std::size_t t = 1; t < 4; ++t)
    for (std::size_t z = 1; z < 5; ++z)
      for (std::size_t y = 1; y < 6; ++y)
        for (std::size_t x = 1; x < 7; ++x)
          if ((x + 2 * y + 3 * z + t) % 3 != 0) image.set(x, y, z, t, (x + z) % 2 ? 1 : second);
  return image;
}

TEST(UploadCodec, DecodesWhatItEncodedOneAndTwoBytesAVoxel) {
  for (const domain::Label second : {domain::Label{2}, domain::Label{700}}) {
    const domain::LabelImage4 image = two_labels(second);
    v1::ImageHeader header;
    const std::string data = encode_upload(image, &header);
    EXPECT_EQ(header.label_type(), second > 255 ? v1::LABEL_TYPE_UINT16 : v1::LABEL_TYPE_UINT8);
    EXPECT_EQ(data.size(), image.voxel_count() * (second > 255 ? 2 : 1));
    EXPECT_EQ(header.sha256(), sha256(data));
    EXPECT_EQ(check_header(header), data.size());
    const domain::LabelImage4 back = decode_upload(header, data, nullptr);
    ASSERT_EQ(back.dims(), image.dims());
    EXPECT_EQ(back.spacing(), image.spacing());
    EXPECT_EQ(back.origin(), image.origin());
    for (std::size_t i = 0; i < image.voxel_count(); ++i)
      ASSERT_EQ(back.at(i), image.at(i)) << "voxel " << i;
  }
}

TEST(UploadCodec, NamesTheWrongFieldOfAHeader) {
  v1::ImageHeader good;
  const std::string data =
      encode_upload(domain::hypersphere_phantom({8, 8, 8, 8}, {1, 1, 1, 1}, 3), &good);
  const std::vector<std::pair<std::function<void(v1::ImageHeader&)>, std::string>> cases = {
      {[](v1::ImageHeader& h) { h.clear_dims(); }, "image.dims is missing"},
      {[](v1::ImageHeader& h) { h.mutable_dims()->set_z(0); }, "image.dims must all be positive"},
      {[](v1::ImageHeader& h) { h.mutable_spacing()->set_t(-1); }, "image.spacing.t"},
      {[](v1::ImageHeader& h) { h.mutable_origin()->set_y(1.0 / 0.0); }, "image.origin.y"},
      {[](v1::ImageHeader& h) { h.set_label_type(v1::LABEL_TYPE_UNSPECIFIED); },
       "image.label_type"},
      {[](v1::ImageHeader& h) { h.set_byte_size(h.byte_size() + 1); }, "image.byte_size"},
      {[](v1::ImageHeader& h) { h.set_sha256("short"); }, "image.sha256"},
  };
  for (const auto& [spoil, field] : cases) {
    v1::ImageHeader h = good;
    spoil(h);
    try {
      check_header(h);
      ADD_FAILURE() << "accepted a header with a bad " << field;
    } catch (const ServiceError& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
  v1::ImageHeader huge = good;
  huge.mutable_dims()->set_x(0xFFFFFFFFu);
  huge.mutable_dims()->set_y(0xFFFFFFFFu);
  huge.mutable_dims()->set_z(0xFFFFFFFFu);
  huge.mutable_dims()->set_t(0xFFFFFFFFu);
  try {
    check_header(huge);
    ADD_FAILURE() << "accepted absurd dims";
  } catch (const ServiceError& e) {
    EXPECT_EQ(e.code(), ErrorCode::resource_exhausted) << e.what();
  }
}

TEST(UploadCodec, RefusesDataThatDoesNotMatchItsHeader) {
  v1::ImageHeader h;
  std::string data = encode_upload(domain::hypersphere_phantom({8, 8, 8, 8}, {1, 1, 1, 1}, 3), &h);
  const auto message = [&](std::string_view bytes) -> std::string {
    try {
      decode_upload(h, bytes, nullptr);
    } catch (const ServiceError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message(std::string_view(data).substr(1)).find("bytes of label data"),
            std::string::npos);
  data[17] ^= 1;
  EXPECT_NE(message(data).find("does not match image.sha256"), std::string::npos);
}

}  // namespace
}  // namespace mesh4d::wire
