// The boundary of a time slice in a compact binary form, for drawing it (the dashboard's
// viewer): each interface's triangles with the labels on either side and the quality of the
// pentatope each was cut from. The layout is in docs/mesh-format.md, "Slice surfaces".
#pragma once

#include <string>

#include "mesh/mesh_slice.h"

namespace mesh4d::mesh {

/// `slice` must be slice_mesh(mesh, t, true): its boundary triangles, their points only.
std::string encode_slice_surface(const Mesh4& mesh, const SliceMesh& slice);

/// The mesh's time span: its period in periodic time, else its vertices' first and last t.
std::array<double, 2> time_span(const Mesh4& mesh);

}  // namespace mesh4d::mesh
