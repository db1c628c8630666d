// Delaunay refinement of a 4D image (Foteinos & Chrisochoides; docs/algorithm.md): the rules
// R1–R5 (R3 first by default) on one thread or on RefineParams::threads workers, then, where
// labels meet, the pinch repair and the relabeling, then the mesh and its statistics.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "delaunay/triangulation.h"
#include "domain/surface_oracle.h"
#include "mesh/mesh4.h"
#include "mesh/mesh_stats.h"
#include "refine/facet_sag.h"
#include "refine/progress.h"
#include "refine/refine_params.h"

namespace mesh4d::refine {

// The stages of a run, in order; the rules' phases run inside several of them and are counted
// apart (Stage::rules), so the stages' times add up to the run's.
enum class Stage {
  start,              // the box, the junctions, every first pentatope admitted
  rules,              // the rules applied (the workers' phases), in every stage
  pinch_repair,       // the pinch counts and the repair points
  relabeling,         // pinches closed by moving pentatopes to a neighbor label
  manifold,           // the manifold scan and its relabeling
  piece_matching,     // each region's pieces matched with the image's
  manifold_sampling,  // ∂Ω sampled where the links still fail
  extraction,         // the output mesh, its boundary offset for the facets' sag
  statistics,         // its quality statistics
};
inline constexpr int kStages = 9;
const char* stage_name(Stage stage);
/// Whether a stage runs on the job's threads (the others run on one).
bool runs_on_threads(Stage stage);

struct StageSeconds {
  std::array<double, kStages> seconds{};
  double& operator[](Stage s) { return seconds[static_cast<int>(s)]; }
  double operator[](Stage s) const { return seconds[static_cast<int>(s)]; }
  /// The time of the stages that run on one thread whatever the job's threads.
  double serial() const;
};

/// What the time caps' flattening did (time_caps.h: flatten_caps).
struct CapFlattening {
  std::size_t relabeled = 0;  // pentatopes given to the ghosts, their centroid past a cap
  std::size_t past = 0;       // output vertices that lay past a cap's hyperplane
  std::size_t flattened = 0;  // of them, moved onto it
  double farthest_left = 0;   // how far past a cap a vertex is left, in time
};

struct RefineResult {
  mesh::Mesh4 mesh;
  mesh::MeshStats stats;
  std::vector<std::string> warnings;
  // Pentatopes given a neighbor's label to close a pinch or make a region's boundary a manifold
  // at a vertex: their circumcenter lies in another label, within their small circumball of the
  // junction.
  std::size_t relabeled = 0;
  // (vertex, label) pairs whose link in the region's boundary is still not a 2-sphere.
  std::size_t non_manifold_left = 0;
  // The manifold sampling's rounds and the surface points they inserted (manifold_sampling.h).
  int manifold_rounds = 0;
  std::size_t manifold_points = 0;
  // The piece matching's mended pieces, both of its passes (piece_matching.h).
  std::size_t pieces_removed = 0, pieces_bridged = 0, pieces_cut = 0;
  // The boundary vertices offset for the facets' sag (RefineParams::sag_offset).
  SagOffset sag;
  // The time caps made flat (time_caps.h; open time with caps only).
  CapFlattening caps;
  // The parallel phases' overheads (Progress): all 0 with one thread.
  std::uint64_t rollbacks = 0;
  double work_seconds = 0;
  double contention_seconds = 0;
  double rolled_back_seconds = 0;
  double idle_seconds = 0;
  double rules_seconds = 0;   // spent applying the rules (the part that runs on the workers)
  double repair_seconds = 0;  // the pinch repair's rounds, the rules after each included
  StageSeconds stages;        // where the time went, wall clock
};

class Refiner final {
 public:
  /// Validates the parameters (ParamError). The oracle must outlive the refiner.
  Refiner(const domain::SurfaceOracle& oracle, const RefineParams& params);
  ~Refiner();
  Refiner(const Refiner&) = delete;
  Refiner& operator=(const Refiner&) = delete;

  /// Refines until no rule applies, then extracts the mesh. Throws Cancelled when the sink asks
  /// to stop and BudgetExceeded past the vertex budget.
  RefineResult run(ProgressSink* sink = nullptr);

  /// The triangulation (for the validity checker in tests).
  const delaunay::Triangulation& triangulation() const;
  /// Tests: every pinch count of the repair after its first is also taken by a full scan, and
  /// a difference (in the pinches, or in any triangle's count) throws std::logic_error;
  /// pinch_counts_checked() says how many were compared.
  void set_pinch_count_check(bool on);
  std::size_t pinch_counts_checked() const;
  /// Tests: around each piece matching a full scan lists the failing links before and after;
  /// one that fails after it, not before, and that the match did not list for the manifold
  /// sampling throws std::logic_error. failing_lists_checked() says how many were compared.
  void set_failing_list_check(bool on);
  std::size_t failing_lists_checked() const;
  /// Tests, periodic time: after every stage each representative's translates must carry its
  /// label (translate_labels.h), or run() throws std::logic_error naming the stage;
  /// translate_labels_checked() says how many translates were compared.
  void set_translate_label_check(bool on);
  std::size_t translate_labels_checked() const;

 private:
  struct Pipeline;
  std::unique_ptr<Pipeline> pipeline_;
};

/// The warnings for boundary vertices whose link fails in a region and for pinched boundary
/// triangles (none for zero counts).
std::vector<std::string> manifold_warnings(std::size_t failing_links, std::size_t pinched);

/// Refines once: Refiner(oracle, params).run(sink).
RefineResult refine(const domain::SurfaceOracle& oracle, const RefineParams& params,
                    ProgressSink* sink = nullptr);

}  // namespace mesh4d::refine
