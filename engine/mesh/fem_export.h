// The whole 4D mesh in the text formats of space-time solvers: MFEM's mesh v1.0 with
// dimension 4, and the libMeshb ASCII .mesh with the Pentatopes keyword (4D adaptation codes
// such as avro). docs/mesh-format.md describes both as written here.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

/// MFEM's geometry code of the pentatope: 7 in mfem's own 4D data (data/cube4d_24.MFEM); other
/// 4D branches number it differently, hence a parameter.
inline constexpr int kMfemPentatopeDefault = 7;
inline constexpr int kMfemTetrahedron = 4;

/// The interfaces of a mesh's boundary, each once: (inner, outer) with inner > outer, or
/// outer = 0 (background). Their 1-based position is the attribute (MFEM) or reference
/// (meshb) of their boundary tetrahedra.
std::vector<std::array<Label, 2>> boundary_interfaces(const Mesh4& mesh);

/// MFEM mesh v1.0: elements (attribute = label, positively oriented), boundary (each
/// interface's tetrahedra once, attribute = its interface number, listed in a comment), vertices.
std::string mfem_mesh(const Mesh4& mesh, int pentatope_geometry = kMfemPentatopeDefault);

/// For a mesh in periodic time, MFEM's periodic convention (Mesh::MakePeriodic): the
/// vertex-to-vertex map, one line per vertex of mfem_mesh's list, its index in the glued cycle
/// (the earlier twin of a vertex past the period, else its own). Empty for open time.
std::string mfem_periodic_vertex_map(const Mesh4& mesh);

/// libMeshb ASCII (MeshVersionFormatted 2, Dimension 4): Vertices, Tetrahedra (reference = the
/// interface number), Pentatopes (reference = label); indices 1-based.
std::string meshb_mesh(const Mesh4& mesh);

}  // namespace mesh4d::mesh
