// Refinement of a cardiac cycle in periodic time (domain/periodic_time.h): the cycle tiled
// three times, refined with every point's copies one period apart, and the middle sheet's
// pentatopes output, glued at the seam (Mesh4::periodic_twins).
#pragma once

#include <string>
#include <vector>

#include "domain/label_image.h"
#include "refine/progress.h"
#include "refine/refiner.h"

namespace mesh4d::refine {

/// Meshes `cycle` (cleaned, not closed) as periodic in time, from half a frame before its first
/// frame to half a frame past its last. RefineParams::period_start and period are set here; the
/// refinement runs on one thread. The closing's warnings about x, y and z go to `warnings`.
/// Throws as Refiner::run and domain::ImageError (fewer than two frames).
RefineResult refine_periodic(const domain::LabelImage4& cycle, const RefineParams& params,
                             ProgressSink* sink, std::vector<std::string>* warnings);

}  // namespace mesh4d::refine
