#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "fuzz_inputs.h"
#include "rest_upload.h"
#include "wire/digest.h"
#include "wire/service_error.h"
#include "wire/upload_codec.h"

namespace mesh4d::fuzz {
namespace {

// Small enough that one input takes milliseconds: the decoders' logic does not depend on size,
// and the limit itself (ImageTooLarge, resource_exhausted) is exercised by headers that say more.
constexpr std::uint64_t kMaxVoxels = 1 << 15;

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::abort();
}

// Errors go to clients: they must never show the server's temporary files. An input that holds
// the files' name prefix may see it echoed; that is no leak.
void check_message(const wire::ServiceError& e, std::string_view input) {
  constexpr std::string_view kPrefix = "mesh4d-upload-";
  if (std::string_view(e.what()).find(kPrefix) != std::string_view::npos &&
      input.find(kPrefix) == std::string_view::npos)
    finding(std::string("an error shows the server's temporary file: ") + e.what());
}

// The labels' checks, as the job manager applies them to an accepted upload.
void decode_labels(const v1::ImageHeader& header, std::string_view labels, std::string_view input) {
  try {
    if (wire::check_header(header) > kMaxVoxels * 2) return;
    const auto image = wire::decode_upload(header, labels, nullptr);
    // Closing pads each axis by at most one background voxel per side and loses no label.
    const auto& d = header.dims();
    const std::uint64_t announced[4] = {d.x(), d.y(), d.z(), d.t()};
    for (int a = 0; a < 4; ++a)
      if (image.dims()[a] < announced[a] || image.dims()[a] > announced[a] + 2)
        finding("a decoded axis is not the header's, give or take the closing's padding");
    const std::size_t width = header.label_type() == v1::LABEL_TYPE_UINT8 ? 1 : 2;
    std::uint64_t sent = 0, kept = 0;
    for (std::size_t i = 0; i + width <= labels.size(); i += width)
      sent += static_cast<std::uint8_t>(labels[i]) +
              (width == 2 ? std::uint64_t{static_cast<std::uint8_t>(labels[i + 1])} << 8 : 0);
    for (std::size_t i = 0; i < image.voxel_count(); ++i) kept += image.at(i);
    if (sent != kept) finding("the decoded labels are not the ones sent");
  } catch (const wire::ServiceError& e) {
    check_message(e, input);
  }
}

void rest_body(std::string_view body) {
  server::RestUpload upload;
  try {
    upload = server::decode_rest_upload(std::string(body), {}, "", kMaxVoxels);
  } catch (const wire::ServiceError& e) {
    check_message(e, body);
    return;
  }
  decode_labels(upload.spec.image(), upload.data, body);
}

void grpc_upload(std::uint8_t mode, std::string_view rest) {
  if (rest.size() < 2) return;
  const std::size_t length =
      static_cast<std::uint8_t>(rest[0]) | (std::size_t{static_cast<std::uint8_t>(rest[1])} << 8);
  rest.remove_prefix(2);
  if (length > rest.size()) return;
  v1::ImageHeader header;
  if (!header.ParseFromArray(rest.data(), static_cast<int>(length))) return;
  const std::string_view labels = rest.substr(length);
  if (mode & 2) header.set_sha256(wire::sha256(labels));
  decode_labels(header, labels, rest);
}

}  // namespace

void exercise_upload_decoder(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;
  const std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] % 2 == 0)
    rest_body(rest);
  else
    grpc_upload(data[0], rest);
}

}  // namespace mesh4d::fuzz
