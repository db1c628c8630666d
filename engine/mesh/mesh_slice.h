// Cross-sections of a space-time mesh at one instant: the 3D mesh a viewer shows at time t
// (ParaView animates a series of them), the volume of each label there (what a cardiologist
// reads off a beating heart: the ventricle's volume curve), and how the benchmarks compare a 4D
// mesh with 3D meshes of single frames.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

/// The section of a 4D mesh by the hyperplane t = time, as a conforming tetrahedral mesh. Each
/// pentatope cut by the plane gives a tetrahedron or a triangular prism (split into three
/// tetrahedra by the smallest-index rule, so that neighbors agree on every shared quad);
/// corners on the plane (within 1e-9 of the mesh's time span) are points of the slice, shared
/// by every section through them, and flat sections are left out.
struct SliceMesh {
  double time = 0;
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::uint32_t, 4>> tetrahedra;  // positively oriented
  std::vector<Label> labels;                             // per tetrahedron
  std::vector<std::uint32_t> pentatopes;                 // per tetrahedron: what it was cut from
  /// The section of the boundary (each interface once): triangles with the labels on either side
  /// (inner > outer, or outer = 0 for the background).
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::array<Label, 2>> triangle_labels;  // {inner, outer}
  std::vector<std::uint32_t> triangle_pentatopes;     // per triangle: its inner pentatope
};

/// Cuts the mesh at t = time; `with_boundary` also cuts the boundary tetrahedra. In periodic
/// time (Mesh4::period) any t is cut, at its place within the period, through the glued cycle.
SliceMesh slice_mesh(const Mesh4& mesh, double time, bool with_boundary);

/// Volume of each label's region in the hyperplane t = `time` (physical units³): the volumes of
/// slice_mesh's tetrahedra, summed per label.
std::map<Label, double> slice_volumes(const Mesh4& mesh, double time);

/// slice_volumes at each of `times` (ascending), in one pass over the pentatopes: each one is
/// cut only at the times inside its own time span, and its section measured alone (any
/// triangulation of a convex section has its volume), so nothing is shared or stored. On up to
/// `threads` threads (shares of at least 4,096 pentatopes); one thread sums in pentatope order.
std::vector<std::map<Label, double>> slice_volumes(const Mesh4& mesh,
                                                   const std::vector<double>& times,
                                                   unsigned threads = 1);

/// Volume of one tetrahedron of a slice (positive for the orientation slice_mesh gives).
double tetrahedron_volume(const SliceMesh& slice, std::size_t i);

}  // namespace mesh4d::mesh
