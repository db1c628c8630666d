#include "job_runner.h"

#include <sstream>

#include "domain/segmentation_cleanup.h"
#include "domain/surface_oracle.h"
#include "mesh/mesh_io.h"
#include "refine/periodic_time.h"
#include "refine/refiner.h"
#include "refine/time_caps.h"
#include "wire/upload_codec.h"

namespace mesh4d::server {
namespace {

// Remembers the refiner's last report, so that the writing phase can repeat its counts: the
// triangulation's counts only grow during a job, and the output mesh's go in MeshStats.
class LastProgress final : public refine::ProgressSink {
 public:
  explicit LastProgress(refine::ProgressSink& next) : next_(next) {}
  void on_progress(const refine::Progress& progress) override {
    last = progress;
    next_.on_progress(progress);
  }
  bool should_abort() override { return next_.should_abort(); }
  refine::Progress last;

 private:
  refine::ProgressSink& next_;
};

}  // namespace

JobOutcome run_job(const v1::ImageHeader& header, const refine::RefineParams& params,
                   const ImagePreparation& preparation, std::string_view input,
                   refine::ProgressSink& sink) {
  JobOutcome out;
  refine::Progress phase;
  phase.phase = refine::Phase::loading;
  sink.on_progress(phase);
  domain::LabelImage4 image =
      wire::decode_unclosed(header, input, &out.warnings, preparation.extend_time_frames);
  // The extension moved the origin by whole frames: it keeps its place in frames.
  if (preparation.time_scale > 0) image.set_time_spacing(preparation.time_scale);
  for (const std::string& w : domain::clean_segmentation(image, preparation.min_island_voxels,
                                                         refine::working_threads(params))
                                  .warnings(preparation.min_island_voxels))
    out.warnings.push_back(w);
  if (image.labels().size() < 2) {
    std::ostringstream why;
    why << "image has a single label everywhere after the segmentation cleanup: there is no "
           "surface to mesh (every piece was smaller than min_island_voxels = "
        << preparation.min_island_voxels << ")";
    throw domain::ImageError(why.str());
  }
  if (sink.should_abort()) throw refine::Cancelled();
  phase.phase = refine::Phase::distance_map;
  sink.on_progress(phase);
  LastProgress refining(sink);
  refine::RefineResult result =
      preparation.periodic ? refine::refine_periodic(image, params, &refining, &out.warnings)
                           : refine::refine_with_time_caps(image, params, &refining, &out.warnings);
  phase = refining.last;
  phase.phase = refine::Phase::writing;
  sink.on_progress(phase);
  const auto bytes = mesh::encode_m4d(result.mesh);
  out.mesh.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  out.stats = result.stats;
  out.relabeled = result.relabeled;
  out.warnings.insert(out.warnings.end(), result.warnings.begin(), result.warnings.end());
  // A periodic mesh: against the cycle. On the job's threads, as many as work now.
  out.certificate = refine::certify(result.mesh, image, refine::working_threads(params));
  for (const std::string& defect : out.certificate.defects())
    out.warnings.push_back("fidelity certificate: " + defect);
  return out;
}

}  // namespace mesh4d::server
