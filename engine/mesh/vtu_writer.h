// VTK XML files of a mesh's time slices, which ParaView and VTK read: each slice an
// UnstructuredGrid (.vtu), a series of them a collection (.pvd) that plays as an animation.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mesh/mesh4.h"
#include "mesh/mesh_slice.h"

namespace mesh4d::mesh {

/// The slice's tetrahedra as a .vtu document (ASCII), with cell data: label, pentatope (its
/// index in `mesh`), and the radius-edge ratio and normalized volume of that pentatope (the
/// quality of the 4D element a tetrahedron belongs to).
std::string slice_vtu(const Mesh4& mesh, const SliceMesh& slice);

/// The slice's boundary triangles as a .vtu document, with cell data inner_label, outer_label.
std::string slice_boundary_vtu(const SliceMesh& slice);

/// A .pvd collection of (time, file name relative to the .pvd) pairs.
std::string pvd_collection(const std::vector<std::pair<double, std::string>>& files);

}  // namespace mesh4d::mesh
