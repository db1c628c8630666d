// When the pinch repair (pinch_repair.cpp) goes on, moves to a finer spacing, or stops.
//
// The repair inserts surface points around pinched triangles, none closer than a spacing to a
// sampled point (Δ/2 first, then halved when nothing else can go in), and lets the rules run
// again; each round's count of pinches says how it went. Measured on the five patients at both
// spacings (docs/refinement.md): at Δ/2 the count falls for about ten rounds, then stays level
// for up to thirty more rounds of a few points each; at Δ/4 the count fell on the phantoms and
// on three patients, but grew on the other seven rows, up to 40 % with twice the vertices and
// three times the time (the short edges set off the radius-edge rule, whose points make new
// pinches). So a level ends after a few rounds without a new low, and a finer level that makes
// the count grow well past where it started, or does not cut it soon, ends the repair:
// relabeling closes the rest.
#pragma once

#include <cstddef>

namespace mesh4d::refine {

class RepairPolicy {
 public:
  enum class Next { repair, finer, stop };

  /// Rounds in a row without a new low that end a level.
  static constexpr int kStallRounds = 4;
  /// A finer level whose count grows past this many times its first one (after its first
  /// round, which must not raise it at all) stops the repair.
  static constexpr double kGrowthLimit = 1.25;
  /// A finer level must pay: its first round must not raise the count, within its first
  /// kTrialRounds the count must fall below kTrialShare of its first one, and a level that
  /// stalls must have brought it below kFinerShare of its first one for a finer level to be
  /// tried; otherwise the repair stops. (On the fourteen refine_bench rows: the finer levels
  /// whose count fell below 90 % of their start, the ventricle's and Pat02's at the files'
  /// spacing, did not rise in their first round and were below 95 % by their second; Pat01's
  /// at the files' spacing bottomed out at 93 %, and the Δ/8 level after it grew by 31 %; the
  /// ten other finer levels never went below 99.8 % of their start, and nine of them rose in
  /// their first round, by 5 to 31 %.)
  static constexpr int kTrialRounds = 2;
  static constexpr double kTrialShare = 0.95, kFinerShare = 0.9;

  /// What to do with `pinches` counted before a round at the current level.
  Next observe(std::size_t pinches) {
    if (pinches == 0) return Next::stop;
    if (!started_) {
      started_ = true;
      first_ = low_ = pinches;
      stalled_ = rounds_ = 0;
      return Next::repair;
    }
    ++rounds_;
    const double limit = rounds_ == 1 ? 1.0 : kGrowthLimit;
    if (level_ > 0 && static_cast<double>(pinches) > limit * static_cast<double>(first_))
      return Next::stop;
    if (pinches < low_) {
      low_ = pinches;
      stalled_ = 0;
    } else {
      ++stalled_;
    }
    if (level_ > 0 && rounds_ == kTrialRounds && !below(kTrialShare)) return Next::stop;
    if (stalled_ < kStallRounds) return Next::repair;
    return level_ > 0 && !below(kFinerShare) ? Next::stop : Next::finer;
  }

  /// The spacing was halved (nothing could go in, or observe() said finer).
  void finer() {
    ++level_;
    started_ = false;
  }

  int level() const { return level_; }

 private:
  bool below(double share) const {
    return static_cast<double>(low_) < share * static_cast<double>(first_);
  }

  int level_ = 0;  // 0 at Δ/2
  bool started_ = false;
  std::size_t first_ = 0, low_ = 0;
  int stalled_ = 0, rounds_ = 0;
};

}  // namespace mesh4d::refine
