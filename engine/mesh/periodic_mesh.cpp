#include "mesh/periodic_mesh.h"

#include <cmath>

namespace mesh4d::mesh {

std::vector<std::uint32_t> glued_vertex_ids(const Mesh4& mesh) {
  std::vector<std::uint32_t> id(mesh.vertices.size());
  for (std::size_t v = 0; v < id.size(); ++v) id[v] = static_cast<std::uint32_t>(v);
  for (const auto& [later, earlier] : mesh.periodic_twins) id[later] = earlier;
  return id;
}

Mesh4 glued(const Mesh4& mesh) {
  Mesh4 out = mesh;
  const std::vector<std::uint32_t> id = glued_vertex_ids(mesh);
  for (auto& p : out.pentatopes)
    for (std::uint32_t& v : p) v = id[v];
  for (BoundaryTetrahedron& b : out.boundary)
    for (std::uint32_t& v : b.vertices) v = id[v];
  return out;
}

Mesh4 unrolled(const Mesh4& mesh) {
  Mesh4 out = mesh;
  out.period = 0;
  out.period_start = 0;
  out.periodic_twins.clear();
  if (!mesh.periodic()) return out;
  // One period earlier, a vertex past the period is its earlier twin; any other gets a copy.
  constexpr auto kNone = static_cast<std::uint32_t>(-1);
  std::vector<std::uint32_t> earlier(mesh.vertices.size(), kNone);
  for (const auto& [later, e] : mesh.periodic_twins) earlier[later] = e;
  const auto copy_of = [&](std::uint32_t v) {
    if (earlier[v] == kNone) {
      earlier[v] = static_cast<std::uint32_t>(out.vertices.size());
      Point4 p = mesh.vertices[v];
      p[3] -= mesh.period;
      out.vertices.push_back(p);
      out.vertex_kinds.push_back(mesh.vertex_kinds[v]);
    }
    return earlier[v];
  };
  const std::size_t n = mesh.pentatopes.size();
  for (std::size_t p = 0; p < n; ++p) {
    auto cell = mesh.pentatopes[p];
    for (std::uint32_t& v : cell) v = copy_of(v);
    out.pentatopes.push_back(cell);
    out.labels.push_back(mesh.labels[p]);
  }
  for (BoundaryTetrahedron b : mesh.boundary) {
    for (std::uint32_t& v : b.vertices) v = copy_of(v);
    b.pentatope += static_cast<std::uint32_t>(n);
    out.boundary.push_back(b);
  }
  return out;
}

double wrapped_time(const Mesh4& mesh, double t) {
  if (!mesh.periodic()) return t;
  double s = t - mesh.period * std::floor((t - mesh.period_start) / mesh.period);
  if (s >= mesh.period_start + mesh.period) s -= mesh.period;
  if (s < mesh.period_start) s += mesh.period;
  return s;
}

}  // namespace mesh4d::mesh
