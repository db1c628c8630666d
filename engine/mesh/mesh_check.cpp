#include "mesh/mesh_check.h"

#include <algorithm>
#include <array>
#include <map>

#include "mesh/periodic_mesh.h"

namespace mesh4d::mesh {

BoundaryCheck check_boundary(const Mesh4& mesh) {
  BoundaryCheck check;
  // In periodic time, triangles at the seam close through the glued vertices.
  const std::vector<std::uint32_t> id = glued_vertex_ids(mesh);
  std::map<std::array<std::uint32_t, 4>, int> triangles;  // (region, sorted triangle) -> count
  for (const auto& b : mesh.boundary) {
    for (auto v : b.vertices) check.non_feature_uses += mesh.vertex_kinds[v] != VertexKind::feature;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<std::uint32_t, 3> t;
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != skip) t[n++] = id[b.vertices[k]];
      std::sort(t.begin(), t.end());
      ++triangles[{b.inner, t[0], t[1], t[2]}];
    }
  }
  check.triangles = triangles.size();
  for (const auto& [key, count] : triangles) {
    check.odd += count % 2;
    check.pinched += count > 2;
  }
  return check;
}

}  // namespace mesh4d::mesh
