// Exact Euclidean feature transform of a 4D label image: for every voxel, which surface voxel is
// nearest (not only how far, which is all ITK's Maurer filter gives).
//
// A surface voxel is one with a face neighbor (±1 along one axis) of another label; both sides
// of every interface, label–label included, are surface voxels, so the interface itself lies
// between two of them. Distances are between voxel centers in physical units (anisotropic
// spacing included).
//
// Algorithm: separable lower envelopes of parabolas (Felzenszwalb & Huttenlocher 2012, as in
// Maurer et al. 2003), one pass per axis, linear in the number of voxels. 4 bytes per voxel for
// the result and 8 more while it runs; ITK's Danielsson vector map needs ~38 (BUILD-NOTES).
#pragma once

#include <cstdint>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {

inline constexpr std::uint32_t kNoFeature = 0xFFFFFFFFu;

/// Whether voxel i (linear index) has a face neighbor with another label.
bool is_surface_voxel(const LabelImage4& image, std::size_t i);

/// For every voxel, the linear index of the nearest surface voxel (kNoFeature when the image has
/// none, that is, a single label everywhere); on up to `threads` threads, the lines of each
/// axis pass split among them (the same result with any number).
std::vector<std::uint32_t> feature_transform(const LabelImage4& image, unsigned threads = 1);

}  // namespace mesh4d::domain
