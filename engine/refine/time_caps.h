// Refinement of an image that is not a cycle, with faithful ends (domain/time_caps.h): ghost
// frames mirror the end frames, the refinement meshes them with the image, and their
// pentatopes are dropped, so that the mesh spans exactly the image's time and its caps are flat.
#pragma once

#include <string>
#include <vector>

#include "domain/label_image.h"
#include "domain/time_caps.h"
#include "refine/progress.h"
#include "refine/refiner.h"

namespace mesh4d::refine {

/// Meshes `image` (cleaned, not yet closed): adds the time caps' ghost frames (cap_frames of Δ
/// and the image's time scale), closes the image, refines it and drops the ghosts. The closing's
/// and the caps' warnings go to `warnings`. Throws as Refiner::run and domain::ImageError.
RefineResult refine_with_time_caps(const domain::LabelImage4& image, const RefineParams& params,
                                   ProgressSink* sink, std::vector<std::string>* warnings);

/// First each pentatope of a label whose vertices all lie on ∂Ω and whose centroid lies past a
/// cap goes to the label's ghost where that is simple (simple_relabeling.h). Then each vertex
/// of a pentatope that stays (not a ghost's) and lies past a cap's hyperplane moves onto it, in
/// time only, guarded as the sag offset's moves (guarded_moves.h) over the pentatopes that
/// stay. `middle` is a time within the image's frames (which side of a cap is past it).
CapFlattening flatten_caps(mesh::Mesh4& mesh, const domain::TimeCaps& caps, double middle,
                           const RefineParams& params);

/// Drops the pentatopes of ghost labels, and the vertices only they used: a facet between a
/// label and its ghost becomes a boundary facet against the outside (label 0). The statistics
/// are those of the mesh left; the refinement's counters stay.
void drop_ghosts(RefineResult& result, const domain::TimeCaps& caps, unsigned threads);

}  // namespace mesh4d::refine
