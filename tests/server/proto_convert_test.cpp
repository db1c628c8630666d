// Conversions between the engine's types and the API's messages: an unset field is the engine's
// default, a set one passes through, and the job record shows every field.
#include "proto_convert.h"

#include <gtest/gtest.h>

#include <set>

namespace mesh4d::server {
namespace {

TEST(ProtoConvert, UnsetFieldsAreTheEnginesDefaults) {
  const refine::RefineParams defaults;
  const refine::RefineParams p = to_engine(v1::RefineParams{});
  EXPECT_EQ(p.delta, defaults.delta);
  EXPECT_EQ(p.radius_edge_bound, defaults.radius_edge_bound);
  EXPECT_EQ(p.picking_ratio, defaults.picking_ratio);
  EXPECT_EQ(p.picking_trials, defaults.picking_trials);
  EXPECT_EQ(p.sliver_bound, defaults.sliver_bound);
  EXPECT_EQ(p.seed, defaults.seed);
  EXPECT_EQ(p.vertex_budget, defaults.vertex_budget);
  EXPECT_EQ(p.rule_order, refine::RuleOrder::r3_first);
  EXPECT_TRUE(p.sag_offset);
  EXPECT_TRUE(to_proto(p, 1).sag_offset()) << "the record says the offset was used";
}

TEST(ProtoConvert, SetFieldsPassThroughBothWays) {
  v1::RefineParams in;
  in.set_delta(2.5);
  in.set_radius_edge_bound(1.7);
  in.set_picking_ratio(0.3);
  in.set_picking_trials(5);
  in.set_sliver_bound(0.05);
  in.set_max_interior_radius(8);
  in.set_rule_order(v1::RULE_ORDER_PAPER);
  in.set_seed(77);
  in.set_vertex_budget(1234);
  in.set_sag_offset(false);
  const refine::RefineParams p = to_engine(in);
  EXPECT_FALSE(p.sag_offset);
  EXPECT_EQ(p.delta, 2.5);
  EXPECT_EQ(p.radius_edge_bound, 1.7);
  EXPECT_EQ(p.picking_ratio, 0.3);
  EXPECT_EQ(p.picking_trials, 5u);
  EXPECT_EQ(p.sliver_bound, 0.05);
  EXPECT_EQ(p.max_interior_radius, 8);
  EXPECT_EQ(p.rule_order, refine::RuleOrder::paper);
  EXPECT_EQ(p.seed, 77u);
  EXPECT_EQ(p.vertex_budget, 1234u);
  const v1::RefineParams out = to_proto(p, 3);
  EXPECT_EQ(out.delta(), 2.5);
  EXPECT_EQ(out.rule_order(), v1::RULE_ORDER_PAPER);
  EXPECT_EQ(out.seed(), 77u);
  EXPECT_EQ(out.threads(), 3u);
  EXPECT_TRUE(out.has_sag_offset());
  EXPECT_FALSE(out.sag_offset());
  EXPECT_EQ(to_proto(to_engine(v1::RefineParams{}), 1).rule_order(), v1::RULE_ORDER_R3_FIRST)
      << "the record names the order used, never UNSPECIFIED";
}

TEST(ProtoConvert, StatsProgressAndPhasesKeepTheirValues) {
  mesh::MeshStats s;
  s.pentatopes = 10;
  s.vertices = 4;
  s.insertions = {1, 2, 3, 4, 5};
  s.radius_edge_ratio.max = 1.9;
  const v1::MeshStats m = to_proto(s);
  EXPECT_EQ(m.pentatopes(), 10u);
  EXPECT_EQ(m.vertices(), 4u);
  refine::Progress p;
  p.vertices = 9;
  p.pentatopes = 99;
  p.phase = refine::Phase::extracting;
  p.work_seconds = 3.5;
  p.contention_seconds = 1.25;
  p.rolled_back_seconds = 0.25;
  p.idle_seconds = 0.5;
  const v1::Progress q = to_proto(p);
  EXPECT_EQ(q.vertices(), 9u);
  EXPECT_EQ(q.pentatopes(), 99u);
  EXPECT_EQ(q.work_seconds(), 3.5);
  EXPECT_EQ(q.contention_seconds(), 1.25);
  EXPECT_EQ(q.rolled_back_seconds(), 0.25);
  EXPECT_EQ(q.idle_seconds(), 0.5);
  std::set<int> phases;
  for (auto phase : {refine::Phase::loading, refine::Phase::distance_map, refine::Phase::refining,
                     refine::Phase::extracting, refine::Phase::writing})
    phases.insert(to_proto(phase));
  EXPECT_EQ(phases.size(), 5u) << "each phase its own value";
  EXPECT_EQ(phases.count(v1::PHASE_UNSPECIFIED), 0u);
}

}  // namespace
}  // namespace mesh4d::server
