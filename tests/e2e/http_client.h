// HTTP calls for the REST tests, made with curl (a foreign client): status, headers and body.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mesh4d::testing {

struct Http {
  int status = 0;  // 0 when curl got no response
  std::string headers;
  std::string body;
  nlohmann::json json() const { return nlohmann::json::parse(body, nullptr, false); }
};

/// One curl call: `args` after the URL; the status and headers come from curl's -D. Its files
/// go to `dir`.
Http curl(const std::string& dir, const std::string& url, std::vector<std::string> args = {},
          int seconds = 60);

/// A response header's value ("" when absent).
std::string header(const Http& h, const std::string& name);

}  // namespace mesh4d::testing
