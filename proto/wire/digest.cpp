#include "wire/digest.h"

#include <cstdint>

#include "mesh/mesh_io.h"

namespace mesh4d::wire {
namespace {

const std::uint8_t* bytes(std::string_view data) {
  return reinterpret_cast<const std::uint8_t*>(data.data());
}

}  // namespace

std::string sha256(std::string_view data) {
  const auto digest = mesh::sha256(bytes(data), data.size());
  return std::string(reinterpret_cast<const char*>(digest.data()), digest.size());
}

std::string sha256_hex(std::string_view data) {
  return mesh::sha256_hex(bytes(data), data.size());
}

}  // namespace mesh4d::wire
