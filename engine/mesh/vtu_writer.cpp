#include "mesh/vtu_writer.h"

#include <limits>
#include <sstream>

#include "delaunay/geometry.h"

namespace mesh4d::mesh {
namespace {

constexpr int kVtkTriangle = 5;
constexpr int kVtkTetra = 10;

// The header and points of an UnstructuredGrid with `cells` cells, each of `corners` points.
template <std::size_t N>
void write_grid(std::ostream& out, const SliceMesh& slice,
                const std::vector<std::array<std::uint32_t, N>>& cells, int vtk_type) {
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
      << "<UnstructuredGrid>\n"
      << "<Piece NumberOfPoints=\"" << slice.points.size() << "\" NumberOfCells=\"" << cells.size()
      << "\">\n"
      << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : slice.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  out << "</DataArray>\n</Points>\n<Cells>\n"
      << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& c : cells) {
    for (std::size_t k = 0; k < N; ++k) out << c[k] << (k + 1 < N ? ' ' : '\n');
  }
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= cells.size(); ++i) out << i * N << '\n';
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < cells.size(); ++i) out << vtk_type << '\n';
  out << "</DataArray>\n</Cells>\n";
}

template <class T, class Value>
void write_cell_array(std::ostream& out, const char* type, const char* name, std::size_t n,
                      Value value) {
  out << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) out << static_cast<T>(value(i)) << '\n';
  out << "</DataArray>\n";
}

void write_footer(std::ostream& out) {
  out << "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

std::ostringstream exact_stream() {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  return out;
}

}  // namespace

std::string slice_vtu(const Mesh4& mesh, const SliceMesh& slice) {
  // The quality of each pentatope cut, measured once however many tetrahedra it gave.
  std::vector<double> rho(slice.tetrahedra.size()), tau(slice.tetrahedra.size());
  for (std::size_t i = 0; i < slice.tetrahedra.size(); ++i) {
    if (i > 0 && slice.pentatopes[i] == slice.pentatopes[i - 1]) {
      rho[i] = rho[i - 1], tau[i] = tau[i - 1];
      continue;
    }
    delaunay::Simplex4 s;
    for (int k = 0; k < 5; ++k) s[k] = mesh.vertices[mesh.pentatopes[slice.pentatopes[i]][k]];
    rho[i] = delaunay::radius_edge_ratio(s);
    tau[i] = delaunay::normalized_volume(s);
  }
  auto out = exact_stream();
  write_grid(out, slice, slice.tetrahedra, kVtkTetra);
  const std::size_t n = slice.tetrahedra.size();
  out << "<CellData Scalars=\"label\">\n";
  write_cell_array<int>(out, "Int32", "label", n, [&](std::size_t i) { return slice.labels[i]; });
  write_cell_array<std::uint32_t>(out, "UInt32", "pentatope", n,
                                  [&](std::size_t i) { return slice.pentatopes[i]; });
  write_cell_array<double>(out, "Float64", "radius_edge_ratio", n,
                           [&](std::size_t i) { return rho[i]; });
  write_cell_array<double>(out, "Float64", "normalized_volume", n,
                           [&](std::size_t i) { return tau[i]; });
  out << "</CellData>\n";
  write_footer(out);
  return out.str();
}

std::string slice_boundary_vtu(const SliceMesh& slice) {
  auto out = exact_stream();
  write_grid(out, slice, slice.triangles, kVtkTriangle);
  const std::size_t n = slice.triangles.size();
  out << "<CellData Scalars=\"inner_label\">\n";
  write_cell_array<int>(out, "Int32", "inner_label", n,
                        [&](std::size_t i) { return slice.triangle_labels[i][0]; });
  write_cell_array<int>(out, "Int32", "outer_label", n,
                        [&](std::size_t i) { return slice.triangle_labels[i][1]; });
  out << "</CellData>\n";
  write_footer(out);
  return out.str();
}

std::string pvd_collection(const std::vector<std::pair<double, std::string>>& files) {
  auto out = exact_stream();
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      << "<Collection>\n";
  for (const auto& [time, file] : files)
    out << "<DataSet timestep=\"" << time << "\" part=\"0\" file=\"" << file << "\"/>\n";
  out << "</Collection>\n</VTKFile>\n";
  return out.str();
}

}  // namespace mesh4d::mesh
