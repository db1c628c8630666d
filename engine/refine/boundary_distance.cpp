#include "refine/boundary_distance.h"

#include <algorithm>
#include <cmath>

namespace mesh4d::refine {

BoundaryDistance measure_boundary_distance(const mesh::Mesh4& mesh,
                                           const domain::SurfaceOracle& oracle,
                                           std::size_t max_samples) {
  BoundaryDistance d;
  if (mesh.boundary.empty() || max_samples == 0) return d;
  const std::size_t stride = std::max<std::size_t>(1, mesh.boundary.size() / max_samples);
  double sum = 0;
  for (std::size_t i = 0; i < mesh.boundary.size(); i += stride) {
    Point4 centroid{};
    for (auto v : mesh.boundary[i].vertices)
      for (int k = 0; k < 4; ++k) centroid[k] += 0.25 * mesh.vertices[v][k];
    // The closest point by descent, not the sampling shortcut the refiner uses. Near the
    // corners of ∂Ω (where three labels meet, the padded time caps) the descent can stop at a
    // farther surface point than one of the tetrahedron's own vertices, which lie on ∂Ω: the
    // nearer of the two still bounds the distance from above, and more tightly.
    const domain::SurfacePoint z = oracle.closest_surface_point(centroid);
    if (z.inner == z.outer) continue;
    double dist = distance(z.point, centroid);
    for (auto v : mesh.boundary[i].vertices)
      dist = std::min(dist, distance(mesh.vertices[v], centroid));
    d.max = std::max(d.max, dist);
    sum += dist;
    ++d.samples;
  }
  if (d.samples) d.mean = sum / static_cast<double>(d.samples);
  return d;
}

}  // namespace mesh4d::refine
