#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "fuzz_inputs.h"
#include "mesh/mesh_io.h"

namespace mesh4d::fuzz {

void exercise_m4d_reader(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;
  std::vector<std::uint8_t> file(data + 1, data + size);
  if (data[0] % 2 == 1) {
    const auto digest = mesh::sha256(file.data(), file.size());
    file.insert(file.end(), digest.begin(), digest.end());
  }
  mesh::Mesh4 decoded;
  try {
    decoded = mesh::decode_m4d(file.data(), file.size());
  } catch (const mesh::MeshFormatError&) {
    return;
  }
  // A reader that accepts a file must understand every byte of it: writing the mesh back gives
  // the same file (padding, reserved bytes and flags included).
  std::vector<std::uint8_t> encoded;
  try {
    encoded = mesh::encode_m4d(decoded);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "fuzz finding: a mesh the reader accepted cannot be written: %s\n",
                 e.what());
    std::abort();
  }
  if (encoded != file) {
    std::fprintf(stderr, "fuzz finding: the mesh read does not write back to the same bytes\n");
    std::abort();
  }
}

}  // namespace mesh4d::fuzz
