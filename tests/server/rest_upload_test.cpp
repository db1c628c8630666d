// A REST submission (rest_upload.h): an image file as the body, the parameters in the query or
// a JSON object; each mistake is refused with a message that names it.
#include "rest_upload.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "../e2e/process.h"
#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "wire/service_error.h"

namespace mesh4d::server {
namespace {

// The phantom as a .nii.gz file's bytes, as `curl --data-binary @file` sends them.
const std::string& nifti_body() {
  static const std::string body = [] {
    const std::string path =
        mesh4d::testing::make_temp_dir("mesh4d-rest-upload") + "/sphere.nii.gz";
    domain::write_nifti(domain::hypersphere_phantom({10, 10, 10, 10}, {1, 1, 1, 1}, 3), path);
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }();
  return body;
}

std::string refusal(const std::string& body, const std::map<std::string, std::string>& query,
                    const std::string& params_json = "") {
  try {
    decode_rest_upload(body, query, params_json);
  } catch (const wire::ServiceError& e) {
    EXPECT_EQ(e.code(), wire::ErrorCode::invalid_argument) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return "";
}

TEST(RestUpload, ReadsTheImageAndTheParametersTheQueryOverriding) {
  const RestUpload u = decode_rest_upload(nifti_body(),
                                          {{"delta", "3"},
                                           {"seed", "18446744073709551615"},
                                           {"name", "sphere"},
                                           {"request_id", "r-1"},
                                           {"time_scale", "2.5"},
                                           {"access_token", "x"},
                                           {"strict", "true"}},
                                          R"({"delta": 4, "rule_order": "paper", "threads": 2})");
  EXPECT_EQ(u.spec.name(), "sphere");
  EXPECT_EQ(u.spec.request_id(), "r-1");
  EXPECT_EQ(u.spec.params().delta(), 3) << "the query over the JSON object";
  EXPECT_EQ(u.spec.params().seed(), 18446744073709551615ull);
  EXPECT_EQ(u.spec.params().rule_order(), v1::RULE_ORDER_PAPER);
  EXPECT_EQ(u.spec.params().threads(), 2u);
  EXPECT_TRUE(u.spec.params().strict());
  EXPECT_EQ(u.spec.image().spacing().t(), 2.5);
  EXPECT_EQ(u.spec.image().dims().x(), 10u);
  EXPECT_EQ(u.data.size(), u.spec.image().byte_size());
  const RestUpload from_query = decode_rest_upload(nifti_body(), {{"params", R"({"delta": 6})"}});
  EXPECT_EQ(from_query.spec.params().delta(), 6);
}

TEST(RestUpload, RefusesEachMistakeNamingIt) {
  EXPECT_NE(refusal("", {}).find("no body"), std::string::npos);
  EXPECT_NE(refusal("hello, not an image", {}).find("not a NIfTI"), std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {{"format", "png"}}).find("format 'png'"), std::string::npos);
  EXPECT_NE(refusal(nifti_body().substr(0, nifti_body().size() / 2), {})
                .find("not a readable label image"),
            std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {{"time_scale", "fast"}}).find("time_scale 'fast'"),
            std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {{"deltaa", "3"}}).find("unknown parameter 'deltaa'"),
            std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {{"rule_order", "fastest"}}).find("rule_order 'fastest'"),
            std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {{"delta", "five"}}).find("delta"), std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {}, "[1]").find("JSON object"), std::string::npos);
}

}  // namespace
}  // namespace mesh4d::server
