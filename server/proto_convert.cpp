#include "proto_convert.h"

#include <string>

#include "wire/service_error.h"

namespace mesh4d::server {
namespace {

v1::RuleCounts counts(const std::array<std::uint64_t, 5>& c) {
  v1::RuleCounts r;
  r.set_r1(c[0]);
  r.set_r2(c[1]);
  r.set_r3(c[2]);
  r.set_r4(c[3]);
  r.set_r5(c[4]);
  return r;
}

v1::Distribution distribution(const mesh::Distribution& d) {
  v1::Distribution r;
  r.set_min(d.min);
  r.set_max(d.max);
  r.set_mean(d.mean);
  r.set_stddev(d.stddev);
  return r;
}

}  // namespace

refine::RefineParams to_engine(const v1::RefineParams& p) {
  refine::RefineParams r;
  if (p.delta() != 0) r.delta = p.delta();
  if (p.radius_edge_bound() != 0) r.radius_edge_bound = p.radius_edge_bound();
  if (p.picking_ratio() != 0) r.picking_ratio = p.picking_ratio();
  if (p.picking_trials() != 0) r.picking_trials = p.picking_trials();
  if (p.sliver_bound() != 0) r.sliver_bound = p.sliver_bound();
  r.max_interior_radius = p.max_interior_radius();
  // An open proto enum carries any number: one this server does not know is a mistake.
  if (!v1::RuleOrder_IsValid(p.rule_order()))
    throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                             "params.rule_order " + std::to_string(p.rule_order()) +
                                 " is not one of 0 (default), 1 (R3 first), 2 (paper)");
  if (p.rule_order() == v1::RULE_ORDER_PAPER) r.rule_order = refine::RuleOrder::paper;
  if (p.seed() != 0) r.seed = p.seed();
  if (p.vertex_budget() != 0) r.vertex_budget = p.vertex_budget();
  if (p.threads() != 0) r.threads = p.threads();
  if (p.has_sag_offset()) r.sag_offset = p.sag_offset();
  return r;
}

bool periodic_time(const v1::RefineParams& p) {
  if (!v1::TimeTopology_IsValid(p.time_topology()))
    throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                             "params.time_topology " + std::to_string(p.time_topology()) +
                                 " is not one of 0 (default, open), 1 (open), 2 (periodic)");
  return p.time_topology() == v1::TIME_TOPOLOGY_PERIODIC;
}

v1::RefineParams to_proto(const refine::RefineParams& p, unsigned threads) {
  v1::RefineParams r;
  r.set_delta(p.delta);
  r.set_radius_edge_bound(p.radius_edge_bound);
  r.set_picking_ratio(p.picking_ratio);
  r.set_picking_trials(p.picking_trials);
  r.set_sliver_bound(p.sliver_bound);
  r.set_max_interior_radius(p.max_interior_radius);
  r.set_rule_order(p.rule_order == refine::RuleOrder::paper ? v1::RULE_ORDER_PAPER
                                                            : v1::RULE_ORDER_R3_FIRST);
  r.set_seed(p.seed);
  r.set_vertex_budget(p.vertex_budget);
  r.set_threads(threads);
  r.set_sag_offset(p.sag_offset);
  return r;
}

v1::MeshStats to_proto(const mesh::MeshStats& s) {
  v1::MeshStats r;
  r.set_vertices(s.vertices);
  r.set_pentatopes(s.pentatopes);
  r.set_boundary_tetrahedra(s.boundary_tetrahedra);
  r.set_shortest_edge(s.shortest_edge);
  *r.mutable_radius_edge_ratio() = distribution(s.radius_edge_ratio);
  *r.mutable_normalized_volume() = distribution(s.normalized_volume);
  for (auto n : s.normalized_volume_histogram) r.add_normalized_volume_histogram(n);
  *r.mutable_insertions() = counts(s.insertions);
  *r.mutable_removals() = counts(s.removals);
  r.set_elapsed_seconds(s.elapsed_seconds);
  r.set_boundary_offset(s.boundary_offset);
  return r;
}

void add_certificate(const refine::FidelityCertificate& c, v1::MeshStats* stats) {
  for (const refine::LabelFidelity& l : c.labels) {
    v1::LabelCertificate* out = stats->add_certificate();
    out->set_label(l.label);
    out->set_mesh_pieces(l.mesh_pieces);
    out->set_touching_pieces(l.touching_pieces);
    out->set_image_pieces(l.image_pieces);
    out->set_image_face_pieces(l.image_face_pieces);
    out->set_non_manifold_vertices(l.non_manifold_vertices);
    out->set_non_manifold_edges(l.non_manifold_edges);
    out->set_non_manifold_triangles(l.non_manifold_triangles);
    out->set_boundary_list_mismatches(l.boundary_list_mismatches);
    out->set_volume(l.volume);
    out->set_voxel_volume(l.voxel_volume);
    out->set_worst_frame_volume_error(l.worst_frame_error);
    out->set_worst_frame_time(l.worst_frame_time);
    out->set_distance_samples(l.distance_samples);
    out->set_mesh_to_image_max(l.mesh_to_image_max);
    out->set_mesh_to_image_mean(l.mesh_to_image_mean);
    out->set_image_to_mesh_max(l.image_to_mesh_max);
    out->set_image_to_mesh_mean(l.image_to_mesh_mean);
  }
}

v1::Phase to_proto(refine::Phase phase) {
  switch (phase) {
    case refine::Phase::loading:
      return v1::PHASE_LOADING;
    case refine::Phase::distance_map:
      return v1::PHASE_DISTANCE_MAP;
    case refine::Phase::refining:
      return v1::PHASE_REFINING;
    case refine::Phase::extracting:
      return v1::PHASE_EXTRACTING;
    case refine::Phase::writing:
      return v1::PHASE_WRITING;
  }
  return v1::PHASE_UNSPECIFIED;
}

v1::Progress to_proto(const refine::Progress& p) {
  v1::Progress r;
  r.set_phase(to_proto(p.phase));
  r.set_vertices(p.vertices);
  r.set_pentatopes(p.pentatopes);
  *r.mutable_insertions() = counts(p.insertions);
  *r.mutable_removals() = counts(p.removals);
  r.set_rollbacks(p.rollbacks);
  r.set_contention_seconds(p.contention_seconds);
  r.set_idle_seconds(p.idle_seconds);
  r.set_work_seconds(p.work_seconds);
  r.set_rolled_back_seconds(p.rolled_back_seconds);
  r.set_elapsed_seconds(p.elapsed_seconds);
  return r;
}

}  // namespace mesh4d::server
