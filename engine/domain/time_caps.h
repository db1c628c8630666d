// Faithful open ends. An image that is not a cycle ends at its first and last frames; closed
// there with background, the object gets a flat cap in time that meets its moving surface along
// a sharp ridge, which refinement at distance Δ rounds off over about Δ of time, so the end
// frames lose volume. Instead, each end frame is mirrored past the end into ghost frames whose
// labels are twins of the real ones (docs/algorithm.md, "The time caps"): the surface continues
// smoothly into the ghosts, the cap becomes the interface between a label and its twin, which
// lies exactly on the hyperplane half a frame past the end frame (the twins weigh alike there),
// and the rules sample it as any interface. Dropping the ghosts' pentatopes leaves a mesh that
// spans exactly the image's time, with flat caps and end frames meshed like the middle ones.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {

struct TimeCaps {
  std::size_t frames = 0;      // ghost frames added at each end that has foreground
  std::vector<Label> real_of;  // by label value: the label a ghost label mirrors, else 0
  std::vector<double> times;   // of the caps' hyperplanes, half a frame past the end frames
  bool is_ghost(Label l) const { return l < real_of.size() && real_of[l] != 0; }
};

/// How many ghost frames the caps need: enough that the ghosts span Δ of time (their own far
/// end, rounded off, then stays clear of the cap), at least one.
std::size_t cap_frames(double delta, double time_scale);

/// `image` with `frames` ghost frames before its first frame and after its last, each a copy of
/// that end frame with every label replaced by its ghost (labels above every label of the
/// image). Ends without foreground get none. The origin moves so that every frame keeps its
/// time. With more than kMaxLabels / 2 labels there is no room for ghosts: the image comes back
/// unchanged and `warning` says so.
LabelImage4 add_time_caps(const LabelImage4& image, std::size_t frames, TimeCaps* caps,
                          std::string* warning);

}  // namespace mesh4d::domain
