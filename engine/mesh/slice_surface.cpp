#include "mesh/slice_surface.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

#include "delaunay/geometry.h"

namespace mesh4d::mesh {
namespace {

constexpr char kMagic[4] = {'M', '4', 'D', 'S'};
constexpr std::uint32_t kVersion = 1;

// Little-endian on every platform the server runs on (x86-64, arm64): the browser reads the
// arrays as typed arrays over the bytes, which are little-endian there too.
template <typename T>
void put(std::string& out, const T& value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace

std::array<double, 2> time_span(const Mesh4& mesh) {
  if (mesh.periodic()) return {mesh.period_start, mesh.period_start + mesh.period};
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Point4& v : mesh.vertices) lo = std::min(lo, v[3]), hi = std::max(hi, v[3]);
  return mesh.vertices.empty() ? std::array<double, 2>{0, 0} : std::array<double, 2>{lo, hi};
}

std::string encode_slice_surface(const Mesh4& mesh, const SliceMesh& slice) {
  // The points the triangles use, renumbered in the order they are first met.
  std::unordered_map<std::uint32_t, std::uint32_t> renumbered;
  std::vector<std::uint32_t> used;
  std::vector<std::uint32_t> corners;
  corners.reserve(3 * slice.triangles.size());
  for (const auto& t : slice.triangles)
    for (std::uint32_t p : t) {
      const auto [it, fresh] = renumbered.try_emplace(p, static_cast<std::uint32_t>(used.size()));
      if (fresh) used.push_back(p);
      corners.push_back(it->second);
    }
  const auto span = time_span(mesh);
  const std::size_t n = used.size(), m = slice.triangles.size();
  std::string out;
  out.reserve(40 + 12 * n + 12 * m + 4 * m + 8 * m);
  out.append(kMagic, 4);
  put(out, kVersion);
  put(out, slice.time);
  put(out, span[0]);
  put(out, span[1]);
  put(out, static_cast<std::uint32_t>(n));
  put(out, static_cast<std::uint32_t>(m));
  for (std::uint32_t p : used)
    for (double c : slice.points[p]) put(out, static_cast<float>(c));
  for (std::uint32_t c : corners) put(out, c);
  for (const auto& l : slice.triangle_labels)
    for (Label x : l) put(out, static_cast<std::uint16_t>(x));
  // The quality of the pentatope each triangle was cut from: the radius-edge ratio, then the
  // normalized volume.
  std::vector<float> ratio(m), volume(m);
  for (std::size_t i = 0; i < m; ++i) {
    delaunay::Simplex4 s;
    const auto& p = mesh.pentatopes[slice.triangle_pentatopes[i]];
    for (int k = 0; k < 5; ++k) s[k] = mesh.vertices[p[k]];
    ratio[i] = static_cast<float>(delaunay::radius_edge_ratio(s));
    volume[i] = static_cast<float>(delaunay::normalized_volume(s));
  }
  for (float x : ratio) put(out, x);
  for (float x : volume) put(out, x);
  return out;
}

}  // namespace mesh4d::mesh
