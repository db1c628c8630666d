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

// Phantoms that provoke what the topology certificate counts (docs/algorithm.md, "Where labels
// meet"); 24⁴ voxels of 1 unit unless given.

/// A ball of label 1 (radius 8) in a shell of label 2 one voxel thick: a wall thinner than any
/// Δ above a voxel.
LabelImage4 thin_wall_phantom(const Dims4& dims = {24, 24, 24, 24},
                              const Vec4& spacing = {1, 1, 1, 1});

/// Two blocks of label 1 joined only through a checkerboard layer: across it, voxels of label 1
/// meet only at edges and corners (diagonal contacts), so the image has two face-connected
/// pieces of label 1 that touch diagonally everywhere along the layer.
LabelImage4 checkerboard_phantom(const Dims4& dims = {24, 24, 24, 24},
                                 const Vec4& spacing = {1, 1, 1, 1});

/// A block of label 1 and a block of label 2 meeting at one voxel corner only.
LabelImage4 corner_contact_phantom(const Dims4& dims = {24, 24, 24, 24},
                                   const Vec4& spacing = {1, 1, 1, 1});

/// A ball of label 1 (radius 8) with a one-voxel island of label 1 outside it and a one-voxel
/// hole inside it.
LabelImage4 island_phantom(const Dims4& dims = {24, 24, 24, 24},
                           const Vec4& spacing = {1, 1, 1, 1});

/// A ball of label 1 (radius 6) and, apart from it, a plate of label 1 one voxel thick (10 × 10
/// voxels in y and z, 6 frames): a piece of the image thinner than any Δ above a voxel, which
/// no circumball of the rules fits in.
LabelImage4 thin_plate_phantom(const Dims4& dims = {24, 24, 24, 24},
                               const Vec4& spacing = {1, 1, 1, 1});

/// A 3D ball (radius 9) cut into three labels by three half-planes through its axis, which
/// rotate by a third of a turn over the time span: a three-label junction moving in time.
LabelImage4 moving_junction_phantom(const Dims4& dims = {24, 24, 24, 24},
                                    const Vec4& spacing = {1, 1, 1, 1});

/// A block of label 2 (4 × 4 × 4 voxels, 16 frames) in label 1 that meets another region of
/// label 2, a wall's corner, only diagonally (voxel edges and corners across x, y and z, in
/// every frame) where most of each block is label 1: two image pieces with a gap near the
/// corners far thinner than Δ, which the mesh must keep apart (a myocardial island near the
/// wall, as on the patients).
LabelImage4 diagonal_island_phantom(const Dims4& dims = {24, 24, 24, 24},
                                    const Vec4& spacing = {1, 1, 1, 1});

/// A ball of label 1 (radius 6) and a small one (radius 3) joined by a bar one voxel thick in
/// y and z over four frames: one image piece whose bridge is far thinner than Δ, so the mesh
/// can cut the small ball off.
LabelImage4 thin_bridge_phantom(const Dims4& dims = {24, 24, 24, 24},
                                const Vec4& spacing = {1, 1, 1, 1});

/// A cycle (frame n would be frame 0) with a ball of label 1 that beats (radius 7 ± 2 voxels)
/// and a ball of label 2 beside it that appears at `first_frame`, grows to radius 7 and is gone
/// again half a cycle later, counted around the cycle: from a late first frame it lives
/// across the end of the cycle and its start.
LabelImage4 appearing_ball_phantom(const Dims4& dims = {36, 24, 24, 12},
                                   const Vec4& spacing = {1, 1, 1, 1}, std::size_t first_frame = 3);

/// The phantoms by name: hypersphere, hypertorus, ventricle, blobs, thin-wall, checkerboard,
/// corner-contact, island, thin-plate, moving-junction, diagonal-island, thin-bridge,
/// appearing-ball.
std::vector<std::string> phantom_names();
/// Throws std::invalid_argument for an unknown name.
LabelImage4 make_phantom(const std::string& name);

}  // namespace mesh4d::domain
