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
  EXPECT_EQ(u.spec.params().time_scale(), 2.5) << "a parameter, not the file's frame interval";
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
  EXPECT_NE(refusal(nifti_body(), {{"time_scale", "fast"}}).find("time_scale"), std::string::npos)
      << refusal(nifti_body(), {{"time_scale", "fast"}});
  EXPECT_NE(refusal(nifti_body(), {{"deltaa", "3"}}).find("unknown parameter 'deltaa'"),
            std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {{"rule_order", "fastest"}}).find("rule_order 'fastest'"),
            std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {{"delta", "five"}}).find("delta"), std::string::npos);
  EXPECT_NE(refusal(nifti_body(), {}, "[1]").find("JSON object"), std::string::npos);
}

// An uploaded header that names a data file elsewhere would make the server read its own disk
// (and hand back a mesh of it): only files that carry their voxels are taken.
TEST(RestUpload, RefusesHeadersThatNameAnotherFile) {
  const std::string dir = mesh4d::testing::make_temp_dir("mesh4d-rest-detached");
  const std::string raw = dir + "/secret.raw";
  {
    std::ofstream out(raw, std::ios::binary);
    for (int i = 0; i < 6 * 6 * 6 * 2; ++i) out.put(static_cast<char>(i % 7 == 0));
  }
  const std::string mha =
      "ObjectType = Image\nNDims = 4\nDimSize = 6 6 6 2\n"
      "ElementType = MET_UCHAR\nElementDataFile = " +
      raw + "\n";
  EXPECT_NE(refusal(mha, {}).find("ElementDataFile"), std::string::npos);
  EXPECT_NE(refusal(mha, {{"format", "mhd"}}).find("ElementDataFile"), std::string::npos);
  for (const char* field : {"data file", "datafile"}) {
    const std::string nrrd = std::string(
                                 "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 6 6 6 2\n"
                                 "encoding: raw\n") +
                             field + ": " + raw + "\n\n";
    EXPECT_NE(refusal(nrrd, {}).find("data file"), std::string::npos) << field;
    EXPECT_NE(refusal(nrrd, {{"format", "nhdr"}}).find("data file"), std::string::npos) << field;
  }
}

// ITK's NRRD reader leaks when loading fails: what cannot be vouched for before it is refused,
// and data that end early are found before it reads them.
TEST(RestUpload, RefusesNrrdHeadersThatCannotBeCheckedFirst) {
  const std::string head = "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 6 6 6 2\n";
  EXPECT_NE(refusal(head + "encoding: ascii\n\n0 1 0", {}).find("raw or gzip"), std::string::npos);
  EXPECT_NE(refusal(head + "encoding: raw\n", {}).find("no empty line"), std::string::npos);
  EXPECT_NE(refusal(head + "encoding:\n\n", {}).find("raw or gzip"), std::string::npos);
  EXPECT_NE(refusal(head + std::string("encoding: raw\n\0\0\n\n", 20), {}).find("plain text"),
            std::string::npos);
  EXPECT_NE(refusal(head + "encoding: raw\nbyte skip: 4\n\n", {}).find("skips"), std::string::npos);
  const std::string short_data = head + "encoding: raw\n\n" + std::string(431, '\1');
  EXPECT_NE(refusal(short_data, {}).find("end early: 431 bytes of the header's 432"),
            std::string::npos);
  EXPECT_NO_THROW(decode_rest_upload(short_data + '\1', {}));
  // As 3D Slicer writes one; a key:=value pair or an unknown field is refused.
  const std::string slicer =
      "NRRD0004\n# Complete NRRD file format specification at:\ntype: unsigned char\n"
      "dimension: 4\nspace: left-posterior-superior-time\nsizes: 6 6 6 2\n"
      "space directions: (1.5,0,0,0) (0,1.5,0,0) (0,0,2,0) (0,0,0,5)\n"
      "kinds: domain domain domain domain\nendian: little\nencoding: raw\n"
      "space origin: (-3,0,1,0)\n\n" +
      std::string(432, '\1');
  EXPECT_NO_THROW(decode_rest_upload(slicer, {}));
  std::string pair = slicer;
  pair.insert(pair.find("endian"), "lab:=heart\n");
  EXPECT_NE(refusal(pair, {}).find("key:=value"), std::string::npos);
  std::string unknown = slicer;
  unknown.insert(unknown.find("endian"), "min: 0\n");
  EXPECT_NE(refusal(unknown, {}).find("\"min\""), std::string::npos);
}

// The header's lines ended with "\r\n", as Windows tools write them.
std::string with_crlf(std::string text) {
  for (std::size_t at = 0; (at = text.find('\n', at)) != std::string::npos; at += 2)
    text.insert(at, "\r");
  return text;
}

// MetaIO parses malformed headers past their end: a MetaImage upload is taken when each line is
// a field it knows, spelt its way, as ITK writes them.
TEST(RestUpload, TakesMetaImageHeadersOnlyInTheFormItReads) {
  const std::string itk_style =
      "ObjectType = Image\nNDims = 4\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
      "CompressedData = False\nTransformMatrix = 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
      "Offset = 0 0 0 0\nCenterOfRotation = 0 0 0 0\nAnatomicalOrientation = ????\n"
      "ElementSpacing = 1.5 1.5 2 5\nDimSize = 6 6 6 2\nElementType = MET_UCHAR\n"
      "ElementDataFile = LOCAL\n";
  std::string voxels(432, '\0');
  for (std::size_t i = 0; i < voxels.size(); i += 5) voxels[i] = 1;
  EXPECT_NO_THROW(decode_rest_upload(itk_style + voxels, {}));
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string body = itk_style + voxels;
    body.replace(body.find(from), from.size(), to);
    return refusal(body, {});
  };
  EXPECT_NE(with("ElementDataFile", "ElEmentDataFile").find("ElEmentDataFile"), std::string::npos);
  EXPECT_NE(with("NDims = 4", "NDims = 4x").find("NDims"), std::string::npos);
  EXPECT_NE(with("NDims = 4", "NDims = 41111111111").find("1 to 4"), std::string::npos);
  EXPECT_NE(with("= LOCAL", "=\r LOCAL").find("plain text"), std::string::npos);
  EXPECT_NO_THROW(decode_rest_upload(with_crlf(itk_style) + voxels, {}));
  EXPECT_NE(with("CompressedData = False", "CompressedDataSize = 99999999").find("more compressed"),
            std::string::npos);
}

}  // namespace
}  // namespace mesh4d::server
