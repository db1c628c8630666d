// Refinement of a cardiac cycle in periodic time (domain/periodic_time.h): the cycle with a
// margin of its own frames past each end (up to the cycle tiled three times), refined with
// every point's copies one period apart, and the middle sheet's pentatopes output, glued at
// the seam (Mesh4::periodic_twins).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "domain/label_image.h"
#include "refine/progress.h"
#include "refine/refiner.h"

namespace mesh4d::refine {

/// How far a labeled pentatope may reach in periodic time, in units of Δ: its circumradius is
/// bounded by this (the patients' labeled pentatopes reach 2.3 Δ at most without the bound; with
/// 3 Δ the covering's margins cost a tenth more time for the same fidelity).
inline constexpr double kLabeledReach = 2;

/// How far the covering's trusted band reaches past each end of the period: a pentatope through
/// a vertex of the middle sheet, of circumradius up to kLabeledReach · Δ, has its circumball in
/// it (twice that reach).
inline double periodic_trusted_reach(double delta) { return 2 * kLabeledReach * delta; }

/// The covering's margin past each end of the period, in frames: the trusted band and one frame
/// more, so that the tiled image's cut-off ends lie a frame away from it; at most a whole period.
std::size_t periodic_margin_frames(const domain::LabelImage4& cycle, double delta);

/// Meshes `cycle` (cleaned, not closed) as periodic in time, from half a frame before its first
/// frame to half a frame past its last. RefineParams::period_start and period are set here; the
/// refinement runs on RefineParams::threads. The closing's warnings about x, y and z go to `warnings`.
/// Throws as Refiner::run and domain::ImageError (fewer than two frames).
RefineResult refine_periodic(const domain::LabelImage4& cycle, const RefineParams& params,
                             ProgressSink* sink, std::vector<std::string>* warnings);

}  // namespace mesh4d::refine
