// The frames' volumes fitted (docs/algorithm.md, "Facet sag"): after the sag offset, each
// label's section at each frame of the image is measured against its voxels, and the boundary
// vertices that the offset moved move again, in space along their normal, by the least
// correction that makes every section match: a field μ per label and frame, interpolated in
// time between the frames, grows a label where it is short. Where a region is thinner than the
// sampling resolves (a systolic cavity two Δ across), the offset's local estimate of the sag
// falls short and the frame's volume with it; the fit closes what is left, a fraction of a
// voxel in depth. The same quality guard holds each move back (guarded_moves.h).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "domain/surface_oracle.h"
#include "mesh/mesh4.h"
#include "refine/refine_params.h"

namespace mesh4d::refine {

struct FrameVolumeFit {
  std::size_t sections = 0;  // (label, frame) pairs fitted
  std::size_t rounds = 0;
  // The relative error of largest magnitude over the sections, before and after the fit.
  double worst_before = 0, worst_after = 0;
  double largest_move = 0;  // of any vertex, physical units
  double seconds = 0;       // wall clock
};

/// The vertices the fit may move: glued ids (mesh::glued_vertex_ids) on one interface between
/// real labels {lower, higher} (the outside 0), with their normal from the lower to the higher.
struct InterfaceVertices {
  std::vector<std::uint32_t> glued;               // by vertex
  std::vector<std::uint32_t> ids;                 // the movers, glued ids
  std::vector<std::array<mesh::Label, 2>> sides;  // by mover
  std::vector<std::array<double, 4>> normals;     // by mover, any length
};

/// Fits the sections of `mesh` at the frames of the oracle's image (within the period, in
/// periodic time) to the image's voxel volumes, a time caps' ghost counting as its real label.
/// Moves are capped at half the smallest spatial spacing per vertex.
FrameVolumeFit fit_frame_volumes(mesh::Mesh4& mesh, const domain::SurfaceOracle& oracle,
                                 const InterfaceVertices& movers, const RefineParams& params);

}  // namespace mesh4d::refine
