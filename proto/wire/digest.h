// SHA-256 as the API carries it: 32 raw bytes in ImageHeader.sha256 and GetResult's checksum,
// 64 hex digits in the REST face's headers.
#pragma once

#include <string>
#include <string_view>

namespace mesh4d::wire {

/// The 32-byte digest of `data`.
std::string sha256(std::string_view data);
/// The same, as 64 lower-case hex digits.
std::string sha256_hex(std::string_view data);

}  // namespace mesh4d::wire
