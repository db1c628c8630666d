// multipart/form-data bodies (RFC 7578) as the REST face receives them: `curl -F image=@FILE -F
// 'params={...}'`. Ours rather than civetweb's, which refuses boundaries of fewer than 4
// characters that RFC 2046 allows (1 to 70).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace mesh4d::server {

struct FormPart {
  std::string name;      // Content-Disposition's name
  std::string filename;  // and its filename, when the part is a file
  std::string body;
};

/// The parts of `body`, whose Content-Type header is `content_type` (with its boundary
/// parameter). Throws wire::ServiceError(invalid_argument) saying what is malformed.
std::vector<FormPart> parse_multipart(std::string_view content_type, std::string_view body);

}  // namespace mesh4d::server
