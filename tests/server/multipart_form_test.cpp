// parse_multipart against bodies written by hand: every boundary length RFC 2046 allows, quoted
// boundaries, a preamble, binary parts, and each malformation refused with its reason.
#include "multipart_form.h"

#include <gtest/gtest.h>

#include "wire/service_error.h"

namespace mesh4d::server {
namespace {

std::string body_with(const std::string& boundary, const std::string& image) {
  return "preamble\r\n--" + boundary +
         "\r\nContent-Disposition: form-data; name=\"image\"; filename=\"a.nii\"\r\n"
         "Content-Type: application/octet-stream\r\n\r\n" +
         image + "\r\n--" + boundary +
         "\r\nContent-Disposition: form-data; name=\"params\"\r\n\r\n{\"delta\": 5}\r\n--" +
         boundary + "--\r\n";
}

TEST(MultipartForm, EveryBoundaryLengthFromOneToSeventy) {
  const std::string image("\0\x1f\x8b\r\n--x\r\nbinary", 17);
  for (std::size_t n = 1; n <= 70; ++n) {
    const std::string boundary(n, 'b');
    const auto parts =
        parse_multipart("multipart/form-data; boundary=" + boundary, body_with(boundary, image));
    ASSERT_EQ(parts.size(), 2u) << n;
    EXPECT_EQ(parts[0].name, "image");
    EXPECT_EQ(parts[0].filename, "a.nii");
    EXPECT_EQ(parts[0].body, image) << n;
    EXPECT_EQ(parts[1].name, "params");
    EXPECT_EQ(parts[1].body, "{\"delta\": 5}");
  }
  const auto quoted =
      parse_multipart("multipart/form-data; BOUNDARY=\"a b\"", body_with("a b", "x"));
  ASSERT_EQ(quoted.size(), 2u);
  EXPECT_EQ(quoted[0].body, "x");
}

TEST(MultipartForm, MalformedBodiesAreRefusedSayingWhat) {
  const auto error_of = [](const std::string& type, const std::string& body) {
    try {
      parse_multipart(type, body);
    } catch (const wire::ServiceError& e) {
      EXPECT_EQ(e.code(), wire::ErrorCode::invalid_argument);
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string type = "multipart/form-data; boundary=zz";
  EXPECT_NE(error_of("multipart/form-data", body_with("zz", "x")).find("1 to 70"),
            std::string::npos);
  EXPECT_NE(error_of("multipart/form-data; boundary=" + std::string(71, 'b'), "").find("1 to 70"),
            std::string::npos);
  EXPECT_NE(error_of(type, "no boundary here").find("no part"), std::string::npos);
  const std::string whole = body_with("zz", "x");
  EXPECT_NE(error_of(type, whole.substr(0, whole.size() - 8)).find("closing boundary"),
            std::string::npos);
  EXPECT_NE(
      error_of(type, "--zz\r\nContent-Disposition: form-data\r\n\r\nx\r\n--zz--").find("no name"),
      std::string::npos);
  EXPECT_NE(error_of(type, "--zz\r\nContent-Disposition: form-data; name=a").find("do not end"),
            std::string::npos);
}

}  // namespace
}  // namespace mesh4d::server
