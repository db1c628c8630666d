// Files the server serves from memory: the dashboard page, its viewer (server/dashboard/viewer.js
// bundled with three.js, gzipped) and the OpenAPI description, compiled in
// (server/embed_files.cmake).
#pragma once

#include <string>
#include <string_view>

namespace mesh4d::server::embedded {

const std::string& dashboard_html();
const std::string& openapi_yaml();
std::string_view viewer_js_gzip();

}  // namespace mesh4d::server::embedded
