#include "refine/fidelity_certificate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "domain/label_census.h"
#include "mesh/mesh_slice.h"
#include "mesh/topology_certificate.h"
#include "refine/two_sided_distance.h"

namespace mesh4d::refine {

std::vector<std::string> FidelityCertificate::defects() const {
  std::vector<std::string> out;
  for (const LabelFidelity& l : labels) {
    if (l.touching_pieces == 0 && l.mesh_pieces == l.image_pieces && l.non_manifold_vertices == 0 &&
        l.non_manifold_edges == 0 && l.non_manifold_triangles == 0 &&
        l.boundary_list_mismatches == 0)
      continue;
    std::ostringstream s;
    s << "label " << l.label << ": the mesh has " << l.mesh_pieces << " pieces ("
      << l.touching_pieces
      << " touching another at a vertex, edge or triangle) where the image has " << l.image_pieces
      << "; " << l.non_manifold_vertices << " non-manifold boundary vertices, "
      << l.non_manifold_edges << " edges, " << l.non_manifold_triangles << " triangles";
    if (l.boundary_list_mismatches)
      s << "; " << l.boundary_list_mismatches << " boundary facets mislisted";
    out.push_back(s.str());
  }
  return out;
}

FidelityCertificate certify(const mesh::Mesh4& mesh, const domain::LabelImage4& image,
                            unsigned threads) {
  std::map<domain::Label, LabelFidelity> by_label;
  for (const mesh::LabelTopology& t : mesh::certify_topology(mesh, threads).labels) {
    LabelFidelity& l = by_label[t.label];
    l.label = t.label;
    l.mesh_pieces = t.components;
    l.touching_pieces = t.touching_components;
    l.non_manifold_vertices = t.non_manifold_vertices;
    l.non_manifold_edges = t.non_manifold_edges;
    l.non_manifold_triangles = t.non_manifold_triangles;
    l.boundary_list_mismatches = t.boundary_list_mismatches;
    l.volume = t.volume;
  }
  const domain::LabelCensus census = mesh.periodic() ? domain::take_periodic_census(image, threads)
                                                     : domain::take_census(image, threads);
  for (const auto& per : census.labels) {
    LabelFidelity& l = by_label[per.label];
    l.label = per.label;
    l.image_pieces = per.components;
    l.image_face_pieces = per.face_components;
    l.voxel_volume = per.volume;
  }
  std::vector<std::size_t> frames;  // those with voxels
  std::vector<double> times;
  for (std::size_t f = 0; f < census.frame_times.size(); ++f)
    if (!census.frame_volumes[f].empty())
      frames.push_back(f), times.push_back(census.frame_times[f]);
  const auto sections = mesh::slice_volumes(mesh, times);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const double t = times[k];
    const auto& section = sections[k];
    for (const auto& [label, voxels] : census.frame_volumes[frames[k]]) {
      const auto it = section.find(label);
      const double error = ((it == section.end() ? 0.0 : it->second) - voxels) / voxels;
      LabelFidelity& l = by_label[label];
      if (std::abs(error) > std::abs(l.worst_frame_error))
        l.worst_frame_error = error, l.worst_frame_time = t;
    }
  }
  for (const TwoSidedDistance& d : two_sided_distances(mesh, image, 1000, threads)) {
    LabelFidelity& l = by_label[d.label];
    l.label = d.label;
    l.distance_samples = std::max(d.mesh_to_image.samples, d.image_to_mesh.samples);
    l.mesh_to_image_max = d.mesh_to_image.max;
    l.mesh_to_image_mean = d.mesh_to_image.mean;
    l.image_to_mesh_max = d.image_to_mesh.max;
    l.image_to_mesh_mean = d.image_to_mesh.mean;
  }
  FidelityCertificate certificate;
  for (const auto& [label, l] : by_label) certificate.labels.push_back(l);
  return certificate;
}

}  // namespace mesh4d::refine
