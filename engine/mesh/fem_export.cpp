#include "mesh/fem_export.h"

#include <algorithm>
#include <limits>
#include <map>
#include <sstream>

#include "delaunay/geometry.h"
#include "mesh/periodic_mesh.h"

namespace mesh4d::mesh {
namespace {

// The pentatope's vertices in positive orientation (FEM codes expect a positive Jacobian).
std::array<std::uint32_t, 5> oriented(const Mesh4& mesh, std::size_t i) {
  std::array<std::uint32_t, 5> v = mesh.pentatopes[i];
  delaunay::Simplex4 s;
  for (int k = 0; k < 5; ++k) s[k] = mesh.vertices[v[k]];
  if (delaunay::signed_volume(s) < 0) std::swap(v[3], v[4]);
  return v;
}

bool listed_once(const BoundaryTetrahedron& f) {
  return f.outer == 0 || f.inner > f.outer;
}

std::map<std::array<Label, 2>, int> interface_numbers(const Mesh4& mesh) {
  std::map<std::array<Label, 2>, int> number;
  int next = 1;
  for (const auto& pair : boundary_interfaces(mesh)) number[pair] = next++;
  return number;
}

std::ostringstream exact_stream() {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  return out;
}

}  // namespace

std::vector<std::array<Label, 2>> boundary_interfaces(const Mesh4& mesh) {
  std::vector<std::array<Label, 2>> pairs;
  for (const auto& f : mesh.boundary)
    if (listed_once(f)) pairs.push_back({f.inner, f.outer});
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

std::string mfem_mesh(const Mesh4& mesh, int pentatope_geometry) {
  const auto number = interface_numbers(mesh);
  auto out = exact_stream();
  out << "MFEM mesh v1.0\n\n# mesh4d space-time mesh: coordinates x y z t\n"
      << "# element attribute = label\n";
  if (mesh.periodic())
    out << "# periodic in time: period " << mesh.period << " from t = " << mesh.period_start
        << "; the vertices past it are glued to those one period earlier by\n"
        << "# Mesh::MakePeriodic(mesh, v2v), v2v read from the .v2v file written beside\n";
  for (const auto& [pair, n] : number)
    out << "# boundary attribute " << n << " = label " << pair[0] << " | "
        << (pair[1] == 0 ? std::string("background") : "label " + std::to_string(pair[1])) << "\n";
  out << "\ndimension\n4\n\nelements\n" << mesh.pentatopes.size() << "\n";
  for (std::size_t i = 0; i < mesh.pentatopes.size(); ++i) {
    out << mesh.labels[i] << ' ' << pentatope_geometry;
    for (std::uint32_t v : oriented(mesh, i)) out << ' ' << v;
    out << '\n';
  }
  std::size_t faces = 0;
  for (const auto& f : mesh.boundary) faces += listed_once(f);
  out << "\nboundary\n" << faces << "\n";
  for (const auto& f : mesh.boundary) {
    if (!listed_once(f)) continue;
    out << number.at({f.inner, f.outer}) << ' ' << kMfemTetrahedron;
    for (std::uint32_t v : f.vertices) out << ' ' << v;
    out << '\n';
  }
  out << "\nvertices\n" << mesh.vertices.size() << "\n4\n";
  for (const auto& p : mesh.vertices)
    out << p[0] << ' ' << p[1] << ' ' << p[2] << ' ' << p[3] << '\n';
  return out.str();
}

std::string mfem_periodic_vertex_map(const Mesh4& mesh) {
  if (!mesh.periodic()) return {};
  std::string out;
  for (std::uint32_t v : glued_vertex_ids(mesh)) out += std::to_string(v) + '\n';
  return out;
}

std::string meshb_mesh(const Mesh4& mesh) {
  const auto number = interface_numbers(mesh);
  auto out = exact_stream();
  out << "MeshVersionFormatted 2\n\nDimension 4\n\nVertices\n" << mesh.vertices.size() << "\n";
  for (const auto& p : mesh.vertices)
    out << p[0] << ' ' << p[1] << ' ' << p[2] << ' ' << p[3] << " 0\n";
  std::size_t faces = 0;
  for (const auto& f : mesh.boundary) faces += listed_once(f);
  out << "\nTetrahedra\n" << faces << "\n";
  for (const auto& f : mesh.boundary) {
    if (!listed_once(f)) continue;
    for (std::uint32_t v : f.vertices) out << v + 1 << ' ';
    out << number.at({f.inner, f.outer}) << '\n';
  }
  out << "\nPentatopes\n" << mesh.pentatopes.size() << "\n";
  for (std::size_t i = 0; i < mesh.pentatopes.size(); ++i) {
    for (std::uint32_t v : oriented(mesh, i)) out << v + 1 << ' ';
    out << mesh.labels[i] << '\n';
  }
  out << "\nEnd\n";
  return out.str();
}

}  // namespace mesh4d::mesh
