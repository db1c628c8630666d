// The pieces of each label as the label function joins them (surface_oracle.h): voxels of the
// label that share a 3D face, and voxels that meet only diagonally, as opposite corners of a
// block of 2^k voxels (k = 2, 3, 4 axes), where the label function gives the block's center to
// their label. There I_L is the share of the block's voxels with label L, so the center goes to
// the label with the most voxels in the block, ties to the higher label (its offset β): a
// diagonal contact between two myocardium voxels is joined unless most of the block is one
// other label. This decides once which way every diagonal contact of the voxels goes, the way
// the mesh of the label function must go; the certificate compares the mesh's pieces with these.
#pragma once

#include <functional>
#include <vector>

#include "domain/face_components.h"

namespace mesh4d::domain {

/// The pieces of the non-zero labels (background voxels get no piece: FacePieces::kNoPiece).
/// `face`, when given, receives the face-connected pieces of the non-zero labels. Those are
/// found on up to `threads` threads.
FacePieces label_function_pieces(const LabelImage4& image,
                                 std::vector<FacePieces::Piece>* face = nullptr,
                                 unsigned threads = 1);

/// Calls fn(i, j) for diagonal joins between different pieces of `face` (face_pieces(image,
/// false)): voxels i and j of one label, opposite corners of a block of 2^k voxels whose center
/// the label function gives to that label, i in a piece that is not its label's largest (every
/// join has such an end). A pair is skipped when earlier calls that returned true join the two
/// pieces already; fn returns whether it joins them.
void for_each_diagonal_join(const LabelImage4& image, const FacePieces& face,
                            const std::function<bool(std::size_t, std::size_t)>& fn);

/// Calls fn(j) for every voxel j that the label function joins directly to voxel i, which has
/// a non-zero label: a face neighbor of that label, or a diagonal one whose block's center has
/// it. `beta`: the offsets by label value (SurfaceOracle::label_offsets). A walk through these
/// finds i's piece of label_function_pieces().
void for_each_joined_neighbor(const LabelImage4& image, const std::vector<double>& beta,
                              std::size_t i, const std::function<void(std::size_t)>& fn);

}  // namespace mesh4d::domain
