// Built-in 4D label images for tests and the demo: analytic shapes voxelized at voxel centers.
#pragma once

#include <string>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {

/// A 4D ball (label 1) of `radius` (physical units) at the image center.
LabelImage4 hypersphere_phantom(const Dims4& dims = {32, 32, 32, 32},
                                const Vec4& spacing = {1, 1, 1, 1}, double radius = 12);

/// A spherical hyper-torus (label 1): points at distance < minor_radius from the circle of
/// radius major_radius in the x-y plane through the image center.
LabelImage4 hypertorus_phantom(const Dims4& dims = {48, 48, 24, 24},
                               const Vec4& spacing = {1, 1, 1, 1}, double major_radius = 14,
                               double minor_radius = 6);

/// A beating left ventricle over one cardiac cycle: blood pool (label 1) inside a myocardial
/// shell (label 2), both ellipsoids along z, the cavity shrinking by a third of its radius and
/// the wall thickening from 8 to 12 mm at end-systole (mid-cycle). Default: the paper's
/// 100×100×44×15 voxels at 1.77×1.77×6 mm, one unit per frame.
LabelImage4 beating_ventricle_phantom(const Dims4& dims = {100, 100, 44, 15},
                                      const Vec4& spacing = {1.77, 1.77, 6, 1});

/// Two 3D balls (label 1) that approach, merge at mid-time and separate again: the space-time
/// object changes topology.
LabelImage4 merging_blobs_phantom(const Dims4& dims = {48, 32, 32, 16},
                                  const Vec4& spacing = {1, 1, 1, 1});

/// The phantoms by name: hypersphere, hypertorus, ventricle, blobs.
std::vector<std::string> phantom_names();
/// Throws std::invalid_argument for an unknown name.
LabelImage4 make_phantom(const std::string& name);

}  // namespace mesh4d::domain
