#include "refine/time_caps.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "delaunay/predicates.h"
#include "domain/surface_oracle.h"
#include "refine/guarded_moves.h"
#include "refine/simple_relabeling.h"

namespace mesh4d::refine {

RefineResult refine_with_time_caps(const domain::LabelImage4& image, const RefineParams& params,
                                   ProgressSink* sink, std::vector<std::string>* warnings) {
  domain::TimeCaps caps;
  std::string caps_warning;
  domain::LabelImage4 capped = domain::add_time_caps(
      image, domain::cap_frames(params.delta, image.spacing()[3]), &caps, &caps_warning);
  for (std::string& w : domain::validate_and_close(capped)) warnings->push_back(std::move(w));
  if (!caps_warning.empty()) warnings->push_back(caps_warning);
  const domain::SurfaceOracle oracle(capped, caps, working_threads(params));
  RefineResult result = refine(oracle, params, sink);
  const double middle = image.voxel_center(0, 0, 0, image.dims()[3] / 2)[3];
  result.caps = flatten_caps(result.mesh, caps, middle, params);
  drop_ghosts(result, caps, working_threads(params));
  return result;
}

namespace {

// A pentatope of a label whose centroid lies past a cap goes to the label's ghost (and is
// dropped with it): the flattening's guard cannot bring its vertices back, since a pentatope
// wholly past the cap would turn. Its circumcenter, before the cap, chose the label.
std::size_t relabel_past_caps(mesh::Mesh4& mesh, const domain::TimeCaps& caps, double middle) {
  std::vector<mesh::Label> ghost_of(caps.real_of.size(), 0);
  for (std::size_t g = 0; g < caps.real_of.size(); ++g)
    if (caps.real_of[g] != 0) ghost_of[caps.real_of[g]] = static_cast<mesh::Label>(g);
  return relabel_simple(mesh, [&](std::uint32_t p) -> mesh::Label {
    double t = 0;
    for (std::uint32_t v : mesh.pentatopes[p]) {
      if (mesh.vertex_kinds[v] != mesh::VertexKind::feature) return 0;
      t += mesh.vertices[v][3] / 5;
    }
    const mesh::Label l = mesh.labels[p];
    bool past = false;
    for (double cap : caps.times) past = past || (cap < middle ? t < cap : t > cap);
    return past && l < ghost_of.size() ? ghost_of[l] : 0;
  });
}

}  // namespace

CapFlattening flatten_caps(mesh::Mesh4& mesh, const domain::TimeCaps& caps, double middle,
                           const RefineParams& params) {
  CapFlattening out;
  if (caps.frames == 0) return out;
  out.relabeled = relabel_past_caps(mesh, caps, middle);
  const std::size_t nv = mesh.vertices.size();
  const auto stays = [&](std::uint32_t p) { return !caps.is_ghost(mesh.labels[p]); };
  std::vector<char> kept(nv, 0);
  for (std::uint32_t p = 0; p < mesh.pentatopes.size(); ++p)
    if (stays(p))
      for (std::uint32_t v : mesh.pentatopes[p]) kept[v] = 1;
  // A vertex past a cap lies on a cap facet near the ridge that R5 sampled on the ghosts' side
  // of the surface (docs/algorithm.md, "The time caps"): in time it goes back to the cap.
  std::vector<Point4> offset(nv, Point4{});
  std::vector<double> target(nv, 0);
  std::vector<std::uint32_t> moving;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (!kept[v]) continue;
    const double t = mesh.vertices[v][3];
    for (double cap : caps.times)
      if (cap < middle ? t < cap : t > cap) {
        offset[v][3] = cap - t;
        target[v] = cap;
        moving.push_back(v);
        break;
      }
  }
  out.past = moving.size();
  if (moving.empty()) return out;
  std::vector<std::uint32_t> self(nv);
  for (std::uint32_t v = 0; v < nv; ++v) self[v] = v;
  const std::vector<Point4> before = mesh.vertices;
  const std::vector<double> scale =
      move_guarded(mesh, before, self, offset, moving, stays, params).scale;
  // A whole move lands within rounding of the cap: put it exactly there, unless that turns a
  // pentatope that stays (checked exactly) where the guarded place did not.
  std::vector<char> snapped(nv, 0);
  for (std::uint32_t v : moving)
    if (scale[v] == 1) mesh.vertices[v][3] = target[v], snapped[v] = 1;
  for (bool undone = true; undone;) {  // until no undoing turns another pentatope
    undone = false;
    for (std::uint32_t p = 0; p < mesh.pentatopes.size(); ++p) {
      const auto& c = mesh.pentatopes[p];
      if (!stays(p) ||
          std::none_of(c.begin(), c.end(), [&](std::uint32_t v) { return snapped[v]; }))
        continue;
      const auto& x = mesh.vertices;
      if (delaunay::orient4(x[c[0]], x[c[1]], x[c[2]], x[c[3]], x[c[4]]) > 0) continue;
      for (std::uint32_t v : c)
        if (snapped[v]) mesh.vertices[v][3] = before[v][3] + offset[v][3], snapped[v] = 0;
      undone = true;
    }
  }
  for (std::uint32_t v : moving) {
    out.flattened += snapped[v];
    if (!snapped[v])
      out.farthest_left = std::max(out.farthest_left, std::abs(target[v] - mesh.vertices[v][3]));
  }
  return out;
}

void drop_ghosts(RefineResult& result, const domain::TimeCaps& caps, unsigned threads) {
  if (caps.frames == 0) return;
  constexpr auto kDropped = std::numeric_limits<std::uint32_t>::max();
  const mesh::Mesh4& in = result.mesh;
  mesh::Mesh4 out;
  std::vector<std::uint32_t> pentatope_index(in.pentatopes.size(), kDropped);
  std::vector<std::uint32_t> vertex_index(in.vertices.size(), kDropped);
  for (std::size_t p = 0; p < in.pentatopes.size(); ++p)
    if (!caps.is_ghost(in.labels[p]))
      for (std::uint32_t v : in.pentatopes[p]) vertex_index[v] = 0;
  // Vertices keep their order.
  for (std::size_t v = 0; v < in.vertices.size(); ++v) {
    if (vertex_index[v] == kDropped) continue;
    vertex_index[v] = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.push_back(in.vertices[v]);
    out.vertex_kinds.push_back(in.vertex_kinds[v]);
  }
  for (std::size_t p = 0; p < in.pentatopes.size(); ++p) {
    if (caps.is_ghost(in.labels[p])) continue;
    pentatope_index[p] = static_cast<std::uint32_t>(out.pentatopes.size());
    auto pentatope = in.pentatopes[p];
    for (std::uint32_t& v : pentatope) v = vertex_index[v];
    out.pentatopes.push_back(pentatope);
    out.labels.push_back(in.labels[p]);
  }
  for (mesh::BoundaryTetrahedron b : in.boundary) {
    if (pentatope_index[b.pentatope] == kDropped) continue;
    b.pentatope = pentatope_index[b.pentatope];
    for (std::uint32_t& v : b.vertices) v = vertex_index[v];
    if (caps.is_ghost(b.outer)) b.outer = 0;
    out.boundary.push_back(b);
  }
  result.mesh = std::move(out);
  const mesh::MeshStats kept = result.stats;
  result.stats = mesh::compute_stats(result.mesh, threads);
  result.stats.insertions = kept.insertions;
  result.stats.removals = kept.removals;
  result.stats.elapsed_seconds = kept.elapsed_seconds;
  result.stats.boundary_offset = kept.boundary_offset;
}

}  // namespace mesh4d::refine
