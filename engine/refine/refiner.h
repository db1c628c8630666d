// Sequential Delaunay refinement of a 4D image (Foteinos & Chrisochoides; ALGORITHM.md,
// "Refinement").
//
// Status: first version. All five rules (R1 to R5, R3 first by default) and an interior sizing
// bound; picking regions for R4 and R5 measure the cavity of each trial point before choosing.
// Tested on the hypersphere (boundary vertices on ∂Ω, closed manifold boundary, radius-edge and
// sliver bounds) and the ventricle (closed region boundaries; pinched triangles remain where
// three labels meet). Not yet checked on every phantom and on real data, and not yet fast.
#pragma once

#include <chrono>
#include <random>
#include <string>
#include <vector>

#include "delaunay/triangulation.h"
#include "domain/surface_oracle.h"
#include "mesh/mesh4.h"
#include "mesh/mesh_stats.h"
#include "refine/feature_index.h"
#include "refine/progress.h"
#include "refine/refine_params.h"

namespace mesh4d::refine {

struct RefineResult {
  mesh::Mesh4 mesh;
  mesh::MeshStats stats;
  std::vector<std::string> warnings;
};

class Refiner {
 public:
  /// Validates the parameters (ParamError). The oracle must outlive the refiner.
  Refiner(const domain::SurfaceOracle& oracle, const RefineParams& params);

  /// Refines until no rule applies, then extracts the mesh. Throws Cancelled when the sink asks
  /// to stop and BudgetExceeded past the vertex budget.
  RefineResult run(ProgressSink* sink = nullptr);

  /// The triangulation (for the validity checker in tests).
  const delaunay::Triangulation& triangulation() const { return tri_; }

 private:
  struct Candidate {
    delaunay::CellId cell;
    mesh4d::VertexId v[5];  // to recognize a reused cell id
  };
  enum Rule { kR1, kR2, kR3, kR4, kR5, kSizing, kNone };

  void insert_box();
  void enqueue(delaunay::CellId c);
  Rule quick_rule(delaunay::CellId c) const;  // a cheap priority guess, confirmed when popped
  bool still_valid(const Candidate& k) const;
  // Decides what to do with a live pentatope: the rule that applies and the point to insert.
  Rule classify(delaunay::CellId c, Point4* point, delaunay::VertexKind* kind);
  Point4 pick_from_region(delaunay::CellId c, const Point4& center, double radius);
  bool find_restricted_facet(delaunay::CellId c, const Point4& center, Point4* surface_center,
                             double* surface_radius) const;
  Point4 pick_on_surface(delaunay::CellId c, const Point4& z, double radius);
  double worst_new_quality(const Point4& p, delaunay::CellId hint);
  void remove_free_vertices_near(mesh4d::VertexId v, std::vector<delaunay::CellId>& created);
  bool ball_meets_surface(const Point4& center, double radius, Point4* cfp) const;
  Point4 clamp_to_box(const Point4& p) const;
  void report(ProgressSink* sink, Phase phase, bool force);
  mesh::Mesh4 extract(std::vector<std::string>& warnings) const;

  const domain::SurfaceOracle& oracle_;
  RefineParams params_;
  delaunay::Triangulation tri_;
  std::array<Point4, 2> box_;
  std::array<std::vector<Candidate>, kNone> queues_;  // one stack per rule
  FeatureIndex features_;
  std::mt19937_64 rng_;       // of the picking regions, seeded by RefineParams::seed
  delaunay::Cavity scratch_;  // trial cavities of the picking regions
  Progress progress_;
  std::chrono::steady_clock::time_point start_, last_report_;
};

}  // namespace mesh4d::refine
