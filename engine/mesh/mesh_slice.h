// Cross-sections of a space-time mesh at one instant: the 3D volume of each label at time t,
// what a cardiologist reads off a beating heart (the ventricle's volume curve), and how the
// benchmarks compare a 4D mesh with 3D meshes of single frames.
#pragma once

#include <map>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

/// Volume of each label's region in the hyperplane t = `time` (physical units³). The section of
/// a pentatope is a tetrahedron or a triangular prism, cut from its edges that cross the plane;
/// pentatopes only touching it add nothing.
std::map<Label, double> slice_volumes(const Mesh4& mesh, double time);

}  // namespace mesh4d::mesh
