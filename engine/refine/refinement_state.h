// What every stage of the refinement reads and the operations write (docs/algorithm.md,
// "Refinement"): the triangulation, each live pentatope's info (its circumball, the label at its
// center, what R1 knows of ∂Ω near it), the index of the feature vertices and the bounding box.
//
// Invariant: every live pentatope has its info. The box and the junctions go in before any info
// exists (insert_box, insert_junctions); from then on each operation calls admit() for the
// pentatopes it made before any other search can reach them, and the cavity searches may ask the
// infos' balls (start_filtering) instead of the exact in-sphere predicate.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <shared_mutex>
#include <vector>

#include "delaunay/conflict_filter.h"
#include "delaunay/geometry.h"
#include "delaunay/triangulation.h"
#include "domain/surface_oracle.h"
#include "refine/feature_index.h"
#include "refine/periodic_covering.h"
#include "refine/refine_params.h"
#include "support/chunked_array.h"
#include "support/reader_biased_mutex.h"

namespace mesh4d::refine {

// What every rule asks of a pentatope, computed once when it is made: its circumball (admit(),
// for each new cell: slots are reused), and the label at its center when first read. Every
// live pentatope has one, the infinite ones too (not finite): a neighbor's info says whether it
// is infinite without a load of its record (the loads of neighbors' records were most of
// find_restricted_facet's time). 64 bytes, aligned: one cache line each (neighbors' infos are
// read in every classification).
struct alignas(64) CellInfo {
  Point4 center;
  double radius = 0;
  double surface_lower = 0;         // a lower bound on the distance from center to ∂Ω
  std::uint32_t surface_voxel = 0;  // where the cfp of center starts (PointFacts)
  // Circumball::center_error rounded up: the cavity searches' in-sphere filter (decide()).
  float center_error = 0;
  // The label at the center plus one, 0 until asked (label_of): most new pentatopes die before
  // anything reads it. Atomic (std::atomic_ref) where read: a thread classifying a neighbor may
  // compute it.
  mutable std::uint32_t label_code = 0;
  bool finite = false;  // false for infinite pentatopes (and exactly flat ones, which none is)
  // Radius over shortest edge ≥ ρ̄ (R3 where inside), measured with the center: the vertices are
  // loaded once per new pentatope.
  bool long_radius = false;
  // Whether surface_lower and surface_voxel are set: only once the pentatope is classified (six
  // in ten pentatopes die before, on the ventricle and the patients).
  bool surface_known = false;
};
static_assert(sizeof(CellInfo) == 64, "one cache line per pentatope's info");

// A queued pentatope: its slot and its vertices, which tell a reused slot from the original.
struct Candidate {
  delaunay::CellId cell;
  mesh4d::VertexId v[5];
};

class RefinementState final : public delaunay::ConflictFilter {
 public:
  /// The oracle must outlive the state; the parameters are validated by the caller.
  RefinementState(const domain::SurfaceOracle& oracle, const RefineParams& params);
  RefinementState(const RefinementState&) = delete;
  RefinementState& operator=(const RefinementState&) = delete;

  /// The corners of the bounding box of the foreground, grown so that they lie at least 2Δ
  /// from ∂Ω.
  void insert_box();
  /// Feature vertices on every triple junction, RefineParams::junction_spacing · Δ apart.
  void insert_junctions();
  /// New pentatopes get their info (not yet their label: label_of()).
  void admit(const std::vector<delaunay::CellId>& cells);
  /// Every live pentatope has its info: the cavity searches may ask the balls (decide()).
  void start_filtering() { tri.set_conflict_filter(this); }
  /// Pentatopes without info are coming (a second run's box): exact predicates only.
  void stop_filtering() { tri.set_conflict_filter(nullptr); }
  /// Storage that never moves, for the worker threads of a parallel phase.
  void prepare_concurrent();

  /// The label at a finite pentatope's circumcenter (or the one relabeling gave it), computed
  /// on the first request. Two threads may compute it at once: they store the same value. In
  /// periodic time every translate of a pentatope gets the same label (translate_invariant_label).
  domain::Label label_of(delaunay::CellId c) const {
    const CellInfo& i = info[c];
    std::atomic_ref<std::uint32_t> code(i.label_code);
    std::uint32_t k = code.load(std::memory_order_relaxed);
    if (k == 0) {
      k = std::uint32_t{covering.active() ? translate_invariant_label(c)
                                          : oracle.label_at(i.center)} +
          1;
      code.store(k, std::memory_order_relaxed);
    }
    return static_cast<domain::Label>(k - 1);
  }
  /// Gives c the label (and, in periodic time, c's twins in the other sheets).
  void set_label(delaunay::CellId c, domain::Label label) {
    info[c].label_code = std::uint32_t{label} + 1;
    if (covering.active()) set_twin_labels(c, label);
  }
  /// The label a pentatope has in the output (0: not output).
  domain::Label output_label(delaunay::CellId c) const { return info[c].finite ? label_of(c) : 0; }
  /// Whether label l's region is one of the output's, whose topology the repairs keep: not the
  /// background, and not a time caps' ghost (dropped at the end, where its pentatopes become
  /// outside as the background's are).
  bool output_region(domain::Label l) const { return l != 0 && oracle.real_label(l) == l; }
  delaunay::Simplex4 simplex_of(delaunay::CellId c) const {
    delaunay::Simplex4 s;
    for (int i = 0; i < 5; ++i) s[i] = tri.store().point(tri.store().cell(c).v[i]);
    return s;
  }
  Point4 centroid_of(delaunay::CellId c) const;
  Point4 clamp_to_box(const Point4& p) const;
  bool still_valid(const Candidate& k) const { return tri.store().still_holds(k.cell, k.v); }
  /// Live pentatope c as a candidate: its slot and its vertices now.
  Candidate candidate(delaunay::CellId c) const {
    Candidate k{c, {}};
    for (int i = 0; i < 5; ++i) k.v[i] = tri.store().cell(c).v[i];
    return k;
  }
  /// Whether a feature vertex lies within r of p (the index is shared by the workers). With
  /// `own_cell_only`, only those in p's cell of the index: a true answer, or perhaps a missed one.
  bool feature_within(const Point4& p, double r, bool own_cell_only = false) const {
    std::shared_lock lock(features_mutex);
    return own_cell_only ? features.any_within_own_cell(p, r) : features.any_within(p, r);
  }

  const domain::SurfaceOracle& oracle;
  const RefineParams params;
  delaunay::Triangulation tri;
  PeriodicCovering covering;             // inactive when time is open
  support::ChunkedArray<CellInfo> info;  // by cell id; blocks never move (parallel phases)
  std::array<Point4, 2> box{};
  FeatureIndex features;
  mutable support::ReaderBiasedMutex features_mutex;

 private:
  // ConflictFilter: the in-sphere questions of cavity searches, answered from the infos'
  // circumballs where rounding cannot change the answer.
  void decide(const delaunay::CellId* cells, int count, const Point4& p,
              std::int8_t* verdict) const override;
  void prefetch(const delaunay::CellId* cells, int count) const override {
    for (int k = 0; k < count; ++k) __builtin_prefetch(&info[cells[k]]);
  }

  void set_twin_labels(delaunay::CellId c, domain::Label label);
  // Periodic time: the label at the circumcenter of c's translate anchored in the middle sheet,
  // computed from the same points in the same order as that translate's own, so the same bit
  // for bit. A translate's own rounded center is not: where the pentatope is near flat the
  // centers of two translates may differ by a good part of a voxel, on either side of a label's
  // boundary, and the glued mesh would have two labels for one pentatope.
  domain::Label translate_invariant_label(delaunay::CellId c) const;

  bool concurrent_ready_ = false;
};

}  // namespace mesh4d::refine
