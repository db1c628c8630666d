// The fidelity certificate of a mesh against the image it was made from, per label: the mesh's
// topology (mesh/topology_certificate.h) beside the image's pieces (domain/label_census.h), the
// region's 4-volume beside the voxels', and the worst frame's 3D volume error. docs/refinement.md,
// "What is checked", says what each count means.
#pragma once

#include <string>
#include <vector>

#include "domain/label_image.h"
#include "mesh/mesh4.h"

namespace mesh4d::refine {

struct LabelFidelity {
  domain::Label label = 0;
  std::size_t mesh_pieces = 0;
  std::size_t touching_pieces = 0;    // mesh pieces meeting another at a vertex, edge or triangle
  std::size_t image_pieces = 0;       // the label function's pieces (domain/label_pieces.h)
  std::size_t image_face_pieces = 0;  // face-connected pieces of the label's voxels
  std::size_t non_manifold_vertices = 0;
  std::size_t non_manifold_edges = 0;
  std::size_t non_manifold_triangles = 0;
  std::size_t boundary_list_mismatches = 0;
  double volume = 0;        // the region's 4-volume
  double voxel_volume = 0;  // the label's voxels' 4-volume
  // Over the frames where the label has voxels: the relative error of the mesh's section at the
  // frame's time against the frame's voxel volume, the largest in magnitude, and that time.
  double worst_frame_error = 0;
  double worst_frame_time = 0;
  // The two-sided distance between the region's boundary in the mesh and in the image
  // (refine/two_sided_distance.h), sampled; physical units.
  std::size_t distance_samples = 0;  // per side, at most
  double mesh_to_image_max = 0, mesh_to_image_mean = 0;
  double image_to_mesh_max = 0, image_to_mesh_mean = 0;
};

struct FidelityCertificate {
  std::vector<LabelFidelity> labels;  // every label of the image or the mesh, ascending
  /// One sentence per label with a topological defect (pieces that touch or differ from the
  /// image's, non-manifold simplices, a wrong boundary list); empty when there is none.
  std::vector<std::string> defects() const;
};

/// `image` is the one meshed (closed, and extended in time where the job asked); for a mesh in
/// periodic time, the cycle (not closed), its last frame next to its first. On up to `threads`
/// threads (the same certificate with any number).
FidelityCertificate certify(const mesh::Mesh4& mesh, const domain::LabelImage4& image,
                            unsigned threads = 1);

}  // namespace mesh4d::refine
