// The reference a user would otherwise reach for: each 3D frame of a 4D label image meshed on
// its own with CGAL's Mesh_3 from the labelled image (refine_bench compares times and volumes).
#pragma once

#include <cstddef>
#include <map>

#include "domain/label_image.h"

namespace mesh4d::bench {

struct FrameMesh {
  double seconds = 0;                      // domain set-up and make_mesh_3
  std::size_t cells = 0;                   // tetrahedra in the complex
  std::map<domain::Label, double> volume;  // per subdomain (label), physical units³
};

/// Frame `t` of `image` meshed by Mesh_3: facet size Δ, facet distance `facet_distance`, cell
/// radius-edge ratio 2, then perturbation and exudation (make_mesh_3's defaults, named here).
FrameMesh mesh_frame_with_cgal(const domain::LabelImage4& image, std::size_t t, double delta,
                               double facet_distance);

}  // namespace mesh4d::bench
