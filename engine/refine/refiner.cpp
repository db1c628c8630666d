// The pipeline of the refinement (docs/algorithm.md): each stage lives in its own file pair.
//
//   refinement_state   the triangulation, each pentatope's info, the feature index
//   rules              which rule a pentatope calls for, and its point (picking regions)
//   operation          one insertion (or R5's insertion and removals), its pentatopes admitted
//   sequential_refiner / parallel_refiner   the rules applied until none applies
//   pinch_scan, facet_log, pinch_repair     pinches where labels meet, sampled away
//   relabeling         the pinches left, closed by moving a few pentatopes to a neighbor label
//   manifold_scan, manifold_relabeling   every region's boundary a manifold at each vertex
//   manifold_sampling  ∂Ω sampled more where no relabeling mends a vertex's link
//   piece_matching     each region's pieces those of the image's label
//   extraction         the output mesh, its boundary offset for the facets' sag
#include "refine/refiner.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "refine/extraction.h"
#include "refine/manifold_relabeling.h"
#include "refine/manifold_sampling.h"
#include "refine/operation.h"
#include "refine/parallel_refiner.h"
#include "refine/periodic_covering.h"
#include "refine/pinch_repair.h"
#include "refine/progress_meter.h"
#include "refine/relabeling.h"
#include "refine/sequential_refiner.h"
#include "refine/translate_labels.h"

namespace mesh4d::refine {
namespace {

constexpr int kUnpinchRounds = 4;  // of free-vertex removal where relabeling is stuck
// Of sampling between the image pieces of a region piece that no cut separates, then matching
// again. Each round samples only where pieces are still joined (a few points); Pat02 in
// periodic time at δ 5 took four (PeriodicTime.APatientsCornerJoinedPieceIsSeparated).
constexpr int kSeparationRounds = 8;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

RefineParams validated(const RefineParams& params) {
  validate(params);
  RefineParams p = params;
  if (p.period > 0) {
    // A labeled pentatope of radius R through a vertex of the middle sheet, or anchored there,
    // has its circumball within 2R of the middle sheet. With R at most half the trusted band
    // (PeriodicCovering::trusted), that ball lies in the band: the pentatope is one of the
    // periodic Delaunay triangulation, not of the cut-off, and its rule's point goes in.
    const double bound =
        PeriodicCovering({p.period_start, p.period}, p.period_margin, p.period_trusted)
            .trusted_reach() /
        2;
    p.max_interior_radius =
        p.max_interior_radius > 0 ? std::min(p.max_interior_radius, bound) : bound;
  }
  return p;
}

// Times the stages one after another; the rules' time inside a stage goes to Stage::rules.
class StageClock {
 public:
  /// `after_lap`, when set, runs after each stage, outside its time (the tests' checks).
  StageClock(const double& rules_seconds, StageSeconds& out,
             std::function<void(Stage)> after_lap = {})
      : rules_(rules_seconds), rules_at_(rules_seconds), out_(out), after_lap_(after_lap) {}
  void lap(Stage stage) {
    auto now = std::chrono::steady_clock::now();
    const double rules = rules_ - rules_at_;
    out_[stage] += std::chrono::duration<double>(now - t_).count() - rules;
    out_[Stage::rules] += rules;
    if (after_lap_) after_lap_(stage), now = std::chrono::steady_clock::now();
    t_ = now;
    rules_at_ = rules_;
  }

 private:
  const double& rules_;
  double rules_at_;
  StageSeconds& out_;
  std::function<void(Stage)> after_lap_;
  std::chrono::steady_clock::time_point t_ = std::chrono::steady_clock::now();
};

}  // namespace

const char* stage_name(Stage stage) {
  switch (stage) {
    case Stage::start:
      return "start";
    case Stage::rules:
      return "rules";
    case Stage::pinch_repair:
      return "pinch repair";
    case Stage::relabeling:
      return "relabeling";
    case Stage::manifold:
      return "manifold";
    case Stage::piece_matching:
      return "piece matching";
    case Stage::manifold_sampling:
      return "manifold sampling";
    case Stage::extraction:
      return "extraction";
    case Stage::statistics:
      return "statistics";
  }
  return "?";
}

bool runs_on_threads(Stage stage) {
  switch (stage) {
    case Stage::rules:
    case Stage::pinch_repair:
    case Stage::extraction:
    case Stage::statistics:
      return true;
    default:
      return false;
  }
}

double StageSeconds::serial() const {
  double sum = 0;
  for (int s = 0; s < kStages; ++s)
    if (!runs_on_threads(static_cast<Stage>(s))) sum += seconds[s];
  return sum;
}

std::vector<std::string> manifold_warnings(std::size_t failing_links, std::size_t pinched) {
  std::vector<std::string> out;
  if (failing_links) {
    std::ostringstream s;
    s << failing_links << " boundary vertices have a link that is not a 2-sphere in "
      << "a region's boundary where labels meet; a smaller delta resolves more of them";
    out.push_back(s.str());
  }
  if (pinched) {
    std::ostringstream s;
    s << pinched << " boundary triangles are pinched (in four or more boundary tetrahedra of "
      << "one label) where labels meet; a smaller delta resolves more of them";
    out.push_back(s.str());
  }
  return out;
}

struct Refiner::Pipeline {
  Pipeline(const domain::SurfaceOracle& oracle, const RefineParams& params)
      : state(oracle, validated(params)),
        rules(state),
        operation(state, rules),
        workers(state.tri, params.seed),
        meter(state.tri, workers),
        parallel(state, operation, workers, meter),
        scan(state),
        repair(state, scan, operation),
        relabeling(state, scan, operation, workers[0]) {}

  // The box's corners and the junctions' feature vertices go in first; then every live
  // pentatope gets its info and is queued, and the cavity searches may ask the balls.
  void start() {
    state.stop_filtering();
    state.insert_box();
    state.insert_junctions();
    std::vector<delaunay::CellId> all;
    for (delaunay::CellId c = 0; c < state.tri.store().cell_slots(); ++c)
      if (state.tri.store().is_live(c)) all.push_back(c);
    operation.admit(workers[0], all);
    state.start_filtering();
  }

  // Applies the rules until none applies: on this thread, or on RefineParams::threads workers.
  void drain(ProgressSink* sink) {
    relabeling.invalidate();
    const auto t0 = std::chrono::steady_clock::now();
    if (state.params.threads > 1)
      parallel.drain(sink);
    else
      drain_sequential(state, operation, workers[0], meter, sink);
    rules_seconds += seconds_since(t0);
  }

  // Where three labels meet the rules guarantee no manifold boundary: sample more of ∂Ω there
  // and refine again; returns the time it took.
  double repair_pinches(ProgressSink* sink) {
    const auto t0 = std::chrono::steady_clock::now();
    auto left = repair.run([&] { drain(sink); },
                           [&](const std::vector<RepairPoint>& points, double spacing) {
                             return parallel.insert_points(points, spacing);
                           });
    relabeling.set_current(std::move(left));
    return seconds_since(t0);
  }

  // What the repair leaves, relabeling closes; where it cannot (a pentatope that would have to
  // move has a free vertex), those free vertices go, the rules run again, and so on, a few
  // times. Returns how many pentatopes moved.
  std::size_t relabel(ProgressSink* sink) {
    std::size_t moved = relabeling.relabel_pinches();
    for (int round = 0; round < kUnpinchRounds && !relabeling.current_pinches().empty(); ++round) {
      if (relabeling.remove_free_vertices_at_pinches() == 0) break;
      drain(sink);
      moved += relabeling.relabel_pinches();
    }
    return moved;
  }

  // Where the relabeling left a region's link failing, ∂Ω is sampled more finely there.
  // `extra`: surface points the piece matching asks for first.
  ManifoldSampling::Outcome sample_manifold(std::vector<NonManifoldVertex> failing,
                                            ProgressSink* sink,
                                            std::vector<RepairPoint> extra = {}) {
    workers.ensure(state.params.threads);  // a log per worker that may run an operation
    ManifoldSampling sampling(state, scan, operation, workers.size());
    return sampling.run(
        std::move(failing), [&] { drain(sink); },
        [&](const std::vector<RepairPoint>& points, double spacing) {
          return parallel.insert_points(points, spacing);
        },
        std::move(extra));
  }

  // The pinches and non-manifold vertices left, the statistics and the counters.
  void finish(RefineResult& result) {
    // In periodic time the glued mesh says (refine_periodic): the covering's other sheets may
    // hold labels that are not yet their representatives'.
    if (!state.covering.active()) {
      // A pinched triangle's vertices fail their links: no count is needed when none does.
      const std::size_t pinches =
          result.non_manifold_left ? relabeling.current_pinches().size() : 0;
      for (std::string& w : manifold_warnings(result.non_manifold_left, pinches))
        result.warnings.push_back(std::move(w));
    }
    result.stats = mesh::compute_stats(result.mesh, working_threads(state.params));
    const Progress done = meter.totals();
    result.stats.insertions = done.insertions;
    result.stats.removals = done.removals;
    result.rollbacks = done.rollbacks;
    result.work_seconds = done.work_seconds;
    result.contention_seconds = done.contention_seconds;
    result.rolled_back_seconds = done.rolled_back_seconds;
    result.idle_seconds = done.idle_seconds;
    result.rules_seconds = rules_seconds;
    result.stats.elapsed_seconds = meter.elapsed_seconds();
    result.stats.boundary_offset = result.sag.largest_offset;
  }

  RefinementState state;
  Rules rules;
  Operation operation;
  Workers workers;
  ProgressMeter meter;
  ParallelRefiner parallel;
  PinchScan scan;
  PinchRepair repair;
  Relabeling relabeling;
  double rules_seconds = 0;
  bool check_failing_lists = false;
  std::size_t failing_lists_checked = 0;
  bool check_translate_labels = false;
  std::size_t translate_labels_checked = 0;
};

Refiner::Refiner(const domain::SurfaceOracle& oracle, const RefineParams& params)
    : pipeline_(std::make_unique<Pipeline>(oracle, params)) {}

Refiner::~Refiner() = default;

namespace {

// set_failing_list_check: the match is run between two full scans, and every pair failing after
// it must have failed before it or be on its list.
PieceMatching checked_match(RefinementState& state, ManifoldRelabeling& step, bool leave_links,
                            bool check, std::size_t& checked) {
  if (!check) return step.match_image_pieces(leave_links);
  std::vector<NonManifoldVertex> before = find_non_manifold_vertices(state);
  PieceMatching matched = step.match_image_pieces(leave_links);
  std::vector<NonManifoldVertex> listed = matched.failing;
  listed.insert(listed.end(), before.begin(), before.end());
  distinct_pairs(listed);
  std::vector<NonManifoldVertex> after = find_non_manifold_vertices(state);
  distinct_pairs(after);
  const auto key = [](const NonManifoldVertex& f) { return std::pair(f.vertex, f.label); };
  for (const NonManifoldVertex& f : after)
    if (!std::binary_search(listed.begin(), listed.end(), f,
                            [&](const auto& a, const auto& b) { return key(a) < key(b); }))
      throw std::logic_error("piece matching left vertex " + std::to_string(f.vertex) +
                             " failing for label " + std::to_string(f.label) + " unlisted");
  ++checked;
  return matched;
}

}  // namespace

RefineResult Refiner::run(ProgressSink* sink) {
  Pipeline& p = *pipeline_;
  p.meter.start();
  RefineResult result;
  const auto check_translates = [&p](Stage stage) {
    const TranslateLabels compared = compare_translate_labels(p.state);
    p.translate_labels_checked += compared.translates;
    if (compared.mismatched > 0)
      throw std::logic_error(
          "after the " + std::string(stage_name(stage)) + " stage, " +
          std::to_string(compared.mismatched) +
          " translates carry another label than their representative: " + compared.first);
  };
  StageClock clock(p.rules_seconds, result.stages,
                   p.check_translate_labels && p.state.covering.active()
                       ? std::function<void(Stage)>(check_translates)
                       : std::function<void(Stage)>());
  p.start();
  clock.lap(Stage::start);
  p.drain(sink);
  clock.lap(Stage::rules);
  // The rules' counts, also for a job that refines faster than the report interval.
  p.meter.report(sink, Phase::refining, true);
  result.repair_seconds = p.repair_pinches(sink);
  clock.lap(Stage::pinch_repair);
  result.relabeled = p.relabel(sink);
  clock.lap(Stage::relabeling);
  ManifoldRelabeling manifold_step(p.state, p.scan);
  ManifoldRelabeling::Outcome manifold = manifold_step.run();
  result.relabeled += manifold.moved;
  clock.lap(Stage::manifold);
  // Pieces first matched with links left to the sampling, then matched again on its mesh.
  PieceMatching matched =
      checked_match(p.state, manifold_step, true, p.check_failing_lists, p.failing_lists_checked);
  result.relabeled += matched.moved;
  const auto count = [&](const PieceMatching& m) {
    result.pieces_removed += m.removed;
    result.pieces_bridged += m.bridged;
    result.pieces_cut += m.cut;
  };
  count(matched);
  std::vector<NonManifoldVertex> failing = std::move(manifold.failing);
  failing.insert(failing.end(), matched.failing.begin(), matched.failing.end());
  distinct_pairs(failing);
  clock.lap(Stage::piece_matching);
  std::vector<RepairPoint> unseparated = std::move(matched.unseparated);
  std::size_t left = 0;  // failing links after the last sampling and match
  // Whether labels moved after the last match: then it runs again, for those moves may have
  // joined a piece to another.
  bool moved_since_match = false;
  const auto match_again = [&] {
    matched = checked_match(p.state, manifold_step, false, p.check_failing_lists,
                            p.failing_lists_checked);
    result.relabeled += matched.moved;
    count(matched);
    moved_since_match = false;
    clock.lap(Stage::piece_matching);
  };
  // The failing links at `around` now, each once.
  const auto failing_at = [&](const std::vector<VertexId>& around) {
    std::vector<NonManifoldVertex> pairs = failing_pairs_at(p.state, around);
    distinct_pairs(pairs);
    return pairs.size();
  };
  for (int round = 0; round <= kSeparationRounds; ++round) {
    const ManifoldSampling::Outcome sampled =
        p.sample_manifold(std::move(failing), sink, std::move(unseparated));
    clock.lap(Stage::manifold_sampling);
    result.relabeled += sampled.moved;
    result.manifold_rounds += sampled.rounds;
    result.manifold_points += sampled.points;
    left = sampled.failing.size();
    if (sampled.points == 0 && sampled.moved == 0 && !moved_since_match) break;
    // The sampling's rules may have joined a cut piece again; a piece no cut separates hands
    // back where ∂Ω is to be sampled between its two image pieces, for another round. The
    // match's moves may leave links failing too: they are sampled in the next round.
    match_again();
    std::vector<VertexId> around;
    for (const NonManifoldVertex& f : sampled.failing) around.push_back(f.vertex);
    for (const NonManifoldVertex& f : matched.failing) around.push_back(f.vertex);
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    if (matched.unseparated.empty() && matched.failing.empty()) {
      // Nothing new: the links the sampling left, as the match leaves them.
      left = failing_at(around);
      break;
    }
    // The links still failing (those the sampling left, and those the match's moves left),
    // mended where the manifold step can.
    const ManifoldRelabeling::Outcome rechecked = manifold_step.run(&around);
    result.relabeled += rechecked.moved;
    moved_since_match = rechecked.moved > 0;
    left = rechecked.failing.size();
    // Another round where pieces are still joined, where links fail that the sampling has not
    // had, or where the mending moved pentatopes after the match.
    const bool fresh = std::any_of(
        rechecked.failing.begin(), rechecked.failing.end(), [&](const NonManifoldVertex& f) {
          return std::none_of(sampled.failing.begin(), sampled.failing.end(),
                              [&](const NonManifoldVertex& g) {
                                return g.vertex == f.vertex && g.label == f.label;
                              });
        });
    if (matched.unseparated.empty() && !fresh && !moved_since_match) break;
    if (round == kSeparationRounds) {
      if (moved_since_match) {
        match_again();
        for (const NonManifoldVertex& f : matched.failing) around.push_back(f.vertex);
        std::sort(around.begin(), around.end());
        around.erase(std::unique(around.begin(), around.end()), around.end());
        left = failing_at(around);
      }
      break;
    }
    failing = rechecked.failing;
    unseparated = std::move(matched.unseparated);
  }
  p.relabeling.invalidate();
  result.non_manifold_left = left;
  p.meter.report(sink, Phase::extracting, true);
  result.mesh = extract(p.state, result.warnings);
  if (p.state.params.sag_offset)
    result.sag = offset_facet_sag(result.mesh, p.state.oracle, p.state.params);
  clock.lap(Stage::extraction);
  p.finish(result);
  clock.lap(Stage::statistics);
  return result;
}

const delaunay::Triangulation& Refiner::triangulation() const {
  return pipeline_->state.tri;
}
void Refiner::set_pinch_count_check(bool on) {
  pipeline_->repair.set_count_check(on);
}
std::size_t Refiner::pinch_counts_checked() const {
  return pipeline_->repair.counts_checked();
}
void Refiner::set_failing_list_check(bool on) {
  pipeline_->check_failing_lists = on;
}
std::size_t Refiner::failing_lists_checked() const {
  return pipeline_->failing_lists_checked;
}
void Refiner::set_translate_label_check(bool on) {
  pipeline_->check_translate_labels = on;
}
std::size_t Refiner::translate_labels_checked() const {
  return pipeline_->translate_labels_checked;
}

RefineResult refine(const domain::SurfaceOracle& oracle, const RefineParams& params,
                    ProgressSink* sink) {
  return Refiner(oracle, params).run(sink);
}

}  // namespace mesh4d::refine
