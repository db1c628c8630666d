#include "job_runner.h"

#include "domain/surface_oracle.h"
#include "mesh/mesh_io.h"
#include "refine/refiner.h"
#include "upload_check.h"

namespace mesh4d::server {

JobOutcome run_job(const v1::ImageHeader& header, const refine::RefineParams& params,
                   std::string_view input, refine::ProgressSink& sink) {
  JobOutcome out;
  refine::Progress phase;
  phase.phase = refine::Phase::loading;
  sink.on_progress(phase);
  const domain::LabelImage4 image = decode_upload(header, input, &out.warnings);
  if (sink.should_abort()) throw refine::Cancelled();
  phase.phase = refine::Phase::distance_map;
  sink.on_progress(phase);
  const domain::SurfaceOracle oracle(image);
  if (sink.should_abort()) throw refine::Cancelled();
  refine::Refiner refiner(oracle, params);
  refine::RefineResult result = refiner.run(&sink);
  phase = {};
  phase.phase = refine::Phase::writing;
  phase.vertices = result.stats.vertices;
  phase.pentatopes = result.stats.pentatopes;
  phase.insertions = result.stats.insertions;
  phase.removals = result.stats.removals;
  phase.elapsed_seconds = result.stats.elapsed_seconds;
  sink.on_progress(phase);
  const auto bytes = mesh::encode_m4d(result.mesh);
  out.mesh.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  out.stats = result.stats;
  out.warnings.insert(out.warnings.end(), result.warnings.begin(), result.warnings.end());
  return out;
}

}  // namespace mesh4d::server
