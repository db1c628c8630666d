// Longer cycles for faithful end frames. A 4D image ends half a frame past its first and last
// frames, where it is closed with background; refinement at sampling distance Δ rounds that
// end off over about Δ of time, so the first and last frames' cross-sections come out too
// small (Pat01 at Δ = 5: cavity −19 % / −14 %, myocardium −28 % / −30 %). Repeating the end
// frames moves the closing away: with Δ worth of frames on each side the end frames are meshed
// like the middle ones (−4 % to 0 %), at the cost of a mesh that spans that much longer in t.
#pragma once

#include <cstddef>

#include "domain/label_image.h"

namespace mesh4d::domain {

/// The most frames extend_time adds at each end.
inline constexpr std::size_t kMaxTimeExtension = 64;

/// `image` with its first frame repeated `frames` times before it and its last frame after it;
/// the origin moves back so that every original frame keeps its time. Throws ImageError over
/// kMaxTimeExtension.
LabelImage4 extend_time(const LabelImage4& image, std::size_t frames);

}  // namespace mesh4d::domain
