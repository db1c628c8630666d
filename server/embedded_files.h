// Files the server serves from memory: the dashboard page and the OpenAPI description, compiled
// in from server/dashboard/index.html and docs/openapi.yaml (server/embed_files.cmake).
#pragma once

#include <string>

namespace mesh4d::server::embedded {

const std::string& dashboard_html();
const std::string& openapi_yaml();

}  // namespace mesh4d::server::embedded
