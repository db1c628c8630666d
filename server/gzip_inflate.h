// Inflating a gzip member held in memory: the embedded viewer for a client that does not accept
// gzip (every browser does; some scripted clients do not ask).
#pragma once

#include <string>
#include <string_view>

namespace mesh4d::server {

/// The inflated bytes; throws std::runtime_error on a damaged stream.
std::string inflate_gzip(std::string_view gzip);

}  // namespace mesh4d::server
