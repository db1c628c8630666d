// How long one frame is along t. Time is a length in a space-time mesh: the time scale (physical
// units per frame) decides how elongated its elements may be and how often the refinement
// samples time. A file's frame interval (ms, s, or none) is not a length, so the default comes
// from the data (docs/algorithm.md, "The time scale"): at least Δ per frame, so that the
// sampling at distance Δ reaches every frame, and at least the distance the boundary moves
// between frames, so that it never leans more than 45° towards a time cap (where a section at
// a frame would cut it at a grazing angle).
#pragma once

#include "domain/label_image.h"

namespace mesh4d::domain {

/// The mean distance the object's boundary moves between two consecutive frames, for the pair
/// where it moves most: the voxels that change label between the frames, times the voxel's
/// volume, over the mean area of the label boundaries in the two frames. Pairs with an empty
/// frame are skipped; 0 for a single frame. In periodic time the last frame and the first are a
/// pair too.
double boundary_motion_per_frame(const LabelImage4& image, bool periodic = false);

/// The default time scale: the larger of Δ and boundary_motion_per_frame(image).
double automatic_time_scale(const LabelImage4& image, double delta, bool periodic = false);

}  // namespace mesh4d::domain
