// Runs one job through the engine: decode and close the image, build the surface oracle, refine,
// encode the mesh. Knows nothing of queues or transports; progress and cancellation go through
// the engine's ProgressSink.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/mesh_stats.h"
#include "mesh4d/v1/mesh4d.pb.h"
#include "refine/fidelity_certificate.h"
#include "refine/progress.h"
#include "refine/refine_params.h"

namespace mesh4d::server {

struct JobOutcome {
  std::string mesh;  // the .m4d bytes
  mesh::MeshStats stats;
  std::vector<std::string> warnings;
  std::size_t relabeled = 0;                // pentatopes given a neighbor's label to close pinches
  refine::FidelityCertificate certificate;  // the mesh against the image meshed
};

/// What is done to the image before it is meshed (RefineParams.time_scale, .extend_time_frames
/// and .min_island_voxels in the proto).
struct ImagePreparation {
  double time_scale = 0;  // the length of a frame along t; 0: the header's spacing.t
  bool periodic = false;  // time_topology periodic: the frame after the last is the first
  std::size_t extend_time_frames = 0;
  std::size_t min_island_voxels = 0;
};

/// Throws refine::Cancelled, refine::BudgetExceeded, wire::ServiceError (bad input) or
/// std::exception.
JobOutcome run_job(const v1::ImageHeader& header, const refine::RefineParams& params,
                   const ImagePreparation& preparation, std::string_view input,
                   refine::ProgressSink& sink);

/// What runs a job: run_job, or a stand-in in the job manager's tests.
using JobRunner = std::function<decltype(run_job)>;

}  // namespace mesh4d::server
