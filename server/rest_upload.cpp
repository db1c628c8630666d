#include "rest_upload.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "domain/image_io.h"
#include "upload_header_policy.h"
#include "wire/params_json.h"
#include "wire/service_error.h"
#include "wire/upload_codec.h"

namespace mesh4d::server {
namespace {

// ITK picks its reader by file name: the body's format, from ?format= or its first bytes.
std::string file_suffix(const std::string& body, const std::map<std::string, std::string>& query) {
  if (const auto it = query.find("format"); it != query.end()) {
    for (const char* known : {"nii", "nii.gz", "nrrd", "nhdr", "mha", "mhd"})
      if (it->second == known) return std::string(".") + known;
    throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                             "format '" + it->second + "' is not one of nii, nii.gz, nrrd, mha");
  }
  if (body.size() >= 2 && static_cast<unsigned char>(body[0]) == 0x1f &&
      static_cast<unsigned char>(body[1]) == 0x8b)
    return ".nii.gz";
  if (body.rfind("NRRD", 0) == 0) return ".nrrd";
  if (body.rfind("ObjectType", 0) == 0 || body.rfind("NDims", 0) == 0) return ".mha";
  if (body.size() >= 348 && (body.compare(344, 4, std::string("n+1\0", 4)) == 0 ||
                             body.compare(344, 4, std::string("n+2\0", 4)) == 0))
    return ".nii";
  throw wire::ServiceError(
      wire::ErrorCode::invalid_argument,
      "the body is not a NIfTI (.nii, .nii.gz), NRRD or MetaImage (.mha) image; "
      "send the file itself (curl --data-binary @FILE) or say ?format=");
}

// The image file, for as long as ITK reads it.
class TemporaryFile {
 public:
  TemporaryFile(const std::string& contents, const std::string& suffix) {
    std::random_device random;
    path_ =
        std::filesystem::temp_directory_path() /
        ("mesh4d-upload-" + std::to_string(::getpid()) + "-" + std::to_string(random()) + suffix);
    std::ofstream out(path_, std::ios::binary);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    // The path is the server's own: the client learns only that the server could not.
    if (!out.flush())
      throw wire::ServiceError(wire::ErrorCode::internal,
                               "the server cannot store the upload for reading (disk full?)");
  }
  ~TemporaryFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

// An error about the temporary file, told about the upload: the server's paths stay private.
std::string about_upload(std::string message, const std::string& path) {
  for (std::size_t at; (at = message.find(path)) != std::string::npos;)
    message.replace(at, path.size(), "the upload");
  return message;
}

// A query value as JSON: a number when it reads as one, true or false, else a string (enum
// names).
nlohmann::json json_value(const std::string& value) {
  if (value == "true" || value == "false") return value == "true";
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  if (!value.empty() && end == value.c_str() + value.size() && std::isfinite(number)) {
    // Parsed as JSON first, so that a 64-bit seed keeps every digit.
    const auto exact = nlohmann::json::parse(value, nullptr, false);
    return exact.is_discarded() ? nlohmann::json(number) : exact;
  }
  return value;
}

}  // namespace

RestUpload decode_rest_upload(const std::string& body,
                              const std::map<std::string, std::string>& query,
                              const std::string& params_json, std::uint64_t max_voxels) {
  if (body.empty())
    throw wire::ServiceError(
        wire::ErrorCode::invalid_argument,
        "the request has no body: send an image file (curl --data-binary @FILE)");
  RestUpload upload;
  const std::string suffix = file_suffix(body, query);
  check_upload_header(body, suffix);
  const TemporaryFile file(body, suffix);
  try {
    const auto image = domain::read_label_image(file.path(), nullptr, max_voxels);
    upload.data = wire::encode_upload(image, upload.spec.mutable_image());
  } catch (const wire::ServiceError&) {
    throw;
  } catch (const domain::ImageTooLarge& e) {
    throw wire::ServiceError(wire::ErrorCode::resource_exhausted,
                             about_upload(e.what(), file.path()));
  } catch (const std::exception& e) {
    throw wire::ServiceError(
        wire::ErrorCode::invalid_argument,
        "the body is not a readable label image: " + about_upload(e.what(), file.path()));
  }
  // Every other query key is a RefineParams field, read by the parser that the client's
  // --params file also goes through (names, types, enum values); the job manager checks the
  // ranges, as for gRPC.
  nlohmann::json params = nlohmann::json::object();
  std::string json_text = params_json;
  if (const auto it = query.find("params"); it != query.end() && json_text.empty())
    json_text = it->second;
  if (!json_text.empty()) {
    params = nlohmann::json::parse(json_text, nullptr, false);
    if (!params.is_object())
      throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                               "params must be a JSON object of RefineParams fields, e.g. "
                               "{\"delta\": 5}");
  }
  for (const auto& [key, value] : query) {
    if (key == "params") continue;
    if (key == "name") {
      upload.spec.set_name(value);
    } else if (key == "request_id") {
      upload.spec.set_request_id(value);
    } else if (key != "format" && key != "access_token") {
      params[key] = json_value(value);
    }
  }
  wire::read_params(params, upload.spec.mutable_params());
  return upload;
}

}  // namespace mesh4d::server
