// refine_bench's comparison with what a user would otherwise do: the 4D mesh of a patient's
// whole cycle against each 3D frame meshed separately by CGAL Mesh_3 (mesh3_frames.h): times,
// and each frame's volume per label against the voxel volume.
#pragma once

#include "domain/label_image.h"

namespace mesh4d::bench {

/// Prints the per-frame table and the totals. Labels 1 and 2 (cavity and myocardium).
void compare_with_mesh3_frames(const char* name, const domain::LabelImage4& image, double delta);

}  // namespace mesh4d::bench
