// A REST submission as the job service takes it: the request body is an image file (NIfTI,
// NRRD or MetaImage, as `curl --data-binary @heart.nii.gz` sends it), read with the engine's
// ITK reader and encoded like the gRPC client's upload; the query string carries the
// parameters, by their RefineParams field names (time_scale among them), plus name, request_id
// and format (or a JSON object of them, as a "params" part or key).
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "mesh4d/v1/mesh4d.pb.h"

namespace mesh4d::server {

struct RestUpload {
  v1::JobSpec spec;
  std::string data;  // raw labels, as SubmitJob's chunks carry them
};

/// Decodes a body and its query parameters; `params_json` (from a multipart request's "params"
/// part, or the "params" query key) is a JSON object of RefineParams fields that the other query
/// keys override. Throws wire::ServiceError(invalid_argument) with a message that names the bad
/// parameter or says what the body is not, or (resource_exhausted) when the file's header
/// announces more than max_voxels voxels (0: no limit): then nothing is inflated or read.
RestUpload decode_rest_upload(const std::string& body,
                              const std::map<std::string, std::string>& query,
                              const std::string& params_json = "", std::uint64_t max_voxels = 0);

}  // namespace mesh4d::server
