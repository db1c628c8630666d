// The checks of a refined mesh that the sequential and the parallel refiner's tests share.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "domain/label_image.h"
#include "domain/surface_oracle.h"
#include "mesh/mesh4.h"
#include "refine/refiner.h"

namespace mesh4d::refine {

// The stated bound on the distance from the output boundary to ∂Ω, as a multiple of δ.
constexpr double kDistanceBound = 0.5;

/// Total 4-volume of the output pentatopes (of one label, or all with 0).
double output_volume(const mesh::Mesh4& m, mesh::Label label = 0);
/// 4-volume of a label's voxels.
double voxel_volume(const domain::LabelImage4& image, domain::Label label);

/// The beating ventricle small enough for δ 8 (50×50×22×8 voxels at 3.54×3.54×12 mm, a time
/// scale of 8 per frame): its cavity and wall over eight frames, as the time tests mesh it.
domain::LabelImage4 small_ventricle();

/// A patient of ../shared/data/heart4d ("Pat01".."Pat05") at the paper's spacing (1.77, 1.77, 6,
/// 1; its first 15 frames, as bench/refine_bench), closed unless `closed` is false (for the
/// steps that close it themselves); nothing where the data are absent.
std::optional<domain::LabelImage4> patient_at_papers_spacing(const std::string& name,
                                                             bool closed = true);

/// Every warning of `r` is the manifold stage's (failing links left where labels meet), and it
/// is there exactly when some are left. GoogleTest expectations.
void expect_only_manifold_warning(const RefineResult& r);

/// After vertex moves (the sag offset, the frames' fit): every pentatope of `moved` positively
/// oriented, exactly, and its quality within what the refinement left in `unmoved`.
void expect_moves_kept_quality(const RefineResult& moved, const RefineResult& unmoved,
                               const RefineParams& params);

/// Fidelity (the refiner's promise): every boundary-tetrahedron vertex is a feature vertex lying on
/// ∂Ω, that is, the two largest interpolated label indicators there are equal (to 1e-6), or no
/// farther from it than `vertex_offset` (RefineResult::sag.largest_offset); the
/// boundary of every label's region is a closed 3-manifold: each of its triangles is in exactly
/// two of the region's boundary tetrahedra (none odd, none pinched in four or more, also where
/// three labels meet); and the boundary stays within `max_distance` of ∂Ω (physical units), plus
/// `vertex_offset`: a point of a facet moves by at most its vertices' largest move.
/// GoogleTest expectations.
void expect_fidelity(const mesh::Mesh4& m, const domain::SurfaceOracle& oracle,
                     const std::vector<domain::Label>& labels, double max_distance,
                     double vertex_offset);

/// The 4D connected components (face neighbors) of each label's voxels that hold no output
/// pentatope of that label: a pentatope counts for the component of the voxel nearest its
/// circumcenter when that voxel has its label. `components` gets how many there are.
std::size_t unmeshed_components(const domain::LabelImage4& image, const mesh::Mesh4& m,
                                std::size_t* components);

/// A sink that asks to stop at its third poll makes run() throw Cancelled, and a budget of 200
/// vertices makes it throw BudgetExceeded, with `threads` workers (hypersphere, δ = 2).
void expect_cancellation_and_budget_stop(unsigned threads);

}  // namespace mesh4d::refine
