// The pieces of each label as the label function joins them (surface_oracle.h): voxels of the
// label that share a 3D face, and voxels that meet only diagonally, as opposite corners of a
// block of 2^k voxels (k = 2, 3, 4 axes), where the label function gives the block's center to
// their label. There I_L is the share of the block's voxels with label L, so the center goes to
// the label with the most voxels in the block, ties to the higher label (its offset β): a
// diagonal contact between two myocardium voxels is joined unless most of the block is one
// other label. This decides once which way every diagonal contact of the voxels goes, the way
// the mesh of the label function must go; the certificate compares the mesh's pieces with these.
#pragma once

#include "domain/face_components.h"

namespace mesh4d::domain {

/// The pieces of the non-zero labels (background voxels get no piece: FacePieces::kNoPiece).
FacePieces label_function_pieces(const LabelImage4& image);

}  // namespace mesh4d::domain
