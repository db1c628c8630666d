#include "mesh3_frames.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>

#include <chrono>

namespace mesh4d::bench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

}  // namespace

FrameMesh mesh_frame_with_cgal(const domain::LabelImage4& image, std::size_t t, double delta,
                               double facet_distance) {
  const auto& d = image.dims();
  const auto& s = image.spacing();
  // An 8-bit CGAL image of the frame; CGAL::Image_3 takes ownership of it.
  _image* frame =
      _createImage(d[0], d[1], d[2], 1, static_cast<float>(s[0]), static_cast<float>(s[1]),
                   static_cast<float>(s[2]), 1, WK_FIXED, SGN_UNSIGNED);
  auto* data = static_cast<unsigned char*>(frame->data);
  for (std::size_t z = 0, i = 0; z < d[2]; ++z)
    for (std::size_t y = 0; y < d[1]; ++y)
      for (std::size_t x = 0; x < d[0]; ++x, ++i)
        data[i] = static_cast<unsigned char>(image.at(x, y, z, t));
  const CGAL::Image_3 cgal_image(frame);

  FrameMesh out;
  const auto start = std::chrono::steady_clock::now();
  const Domain domain = Domain::create_labeled_image_mesh_domain(cgal_image);
  namespace p = CGAL::parameters;
  const Criteria criteria(p::facet_size = delta, p::facet_distance = facet_distance,
                          p::cell_radius_edge_ratio = 2.0);
  const C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, p::perturb(), p::exude());
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    const auto& tr = c3t3.triangulation();
    const double v = std::abs(CGAL::to_double(tr.tetrahedron(c).volume()));
    out.volume[static_cast<domain::Label>(c3t3.subdomain_index(c))] += v;
    ++out.cells;
  }
  return out;
}

}  // namespace mesh4d::bench
