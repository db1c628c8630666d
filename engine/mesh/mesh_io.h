// The native binary mesh format, .m4d (docs/mesh-format.md): versioned, little-endian, with a
// SHA-256 of the whole content at the end. What the service returns and the client exports from.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

inline constexpr std::uint32_t kM4dVersion = 1;
/// Flag bit: the mesh is periodic in time (its period and seam twins follow the boundary).
inline constexpr std::uint32_t kPeriodicTimeFlag = 1;

/// A file or buffer that is not a valid .m4d: the message says what is wrong.
class MeshFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Serializes the mesh. Throws std::invalid_argument for an inconsistent mesh (sizes that do not
/// match, vertex ids out of range, a zero label).
std::vector<std::uint8_t> encode_m4d(const Mesh4& mesh);
/// Parses and checks a buffer: magic, version, sizes, checksum, ids in range.
Mesh4 decode_m4d(const std::uint8_t* data, std::size_t size);

void write_m4d(const Mesh4& mesh, const std::string& path);
Mesh4 read_m4d(const std::string& path);

/// SHA-256 of a buffer (32 bytes), as stored in the file and sent by the service.
std::array<std::uint8_t, 32> sha256(const std::uint8_t* data, std::size_t size);
/// The same digest as 64 lowercase hex digits (the REST API's X-Mesh4d-SHA256 header).
std::string sha256_hex(const std::uint8_t* data, std::size_t size);

}  // namespace mesh4d::mesh
