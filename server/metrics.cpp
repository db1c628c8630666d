#include "metrics.h"

#include <CivetServer.h>
#include <google/protobuf/util/time_util.h>

#include <cctype>

#include "civetweb_tls.h"

namespace mesh4d::server {
namespace {

// TLS on the metrics port when the server has it (civetweb_tls.h); civetweb copies nothing from
// the callbacks, so they live as long as the process.
const CivetCallbacks& tls_callbacks() {
  static const CivetCallbacks callbacks = [] {
    CivetCallbacks c{};
    add_tls_setup(c);
    return c;
  }();
  return callbacks;
}

std::string state_label(int state) {
  std::string name = v1::JobState_Name(static_cast<v1::JobState>(state)).substr(10);
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;  // "queued", "running", ...
}

}  // namespace

ServiceMetrics::ServiceMetrics(const std::string& listen)
    : registry_(std::make_shared<prometheus::Registry>()),
      exposer_(std::make_unique<prometheus::Exposer>(
          std::vector<std::string>{"listening_ports", civetweb_listening_port(listen),
                                   "num_threads", "2"},
          &tls_callbacks())) {
  auto& jobs = prometheus::BuildGauge()
                   .Name("mesh4d_jobs")
                   .Help("Jobs by state (queued is the queue depth)")
                   .Register(*registry_);
  auto& finished = prometheus::BuildCounter()
                       .Name("mesh4d_jobs_finished_total")
                       .Help("Jobs that ended, by final state")
                       .Register(*registry_);
  for (int s = v1::JOB_STATE_QUEUED; s <= v1::JOB_STATE_CANCELLED; ++s) {
    jobs_[s] = &jobs.Add({{"state", state_label(s)}});
    if (s >= v1::JOB_STATE_SUCCEEDED) finished_[s] = &finished.Add({{"state", state_label(s)}});
  }
  duration_ = &prometheus::BuildHistogram()
                   .Name("mesh4d_job_duration_seconds")
                   .Help("Running time of jobs that succeeded")
                   .Register(*registry_)
                   .Add({}, prometheus::Histogram::BucketBoundaries{0.1, 0.5, 1, 5, 10, 30, 60, 300,
                                                                    900, 3600});
  auto& insertions = prometheus::BuildCounter()
                         .Name("mesh4d_insertions_total")
                         .Help("Vertices inserted by refinement rule, over finished jobs")
                         .Register(*registry_);
  static const char* kRules[5] = {"R1", "R2", "R3", "R4", "R5"};
  for (int r = 0; r < 5; ++r) insertions_[r] = &insertions.Add({{"rule", kRules[r]}});
  rollbacks_ = &prometheus::BuildCounter()
                    .Name("mesh4d_rollbacks_total")
                    .Help("Speculative operations undone by the parallel refiner")
                    .Register(*registry_)
                    .Add({});
  pentatopes_ = &prometheus::BuildCounter()
                     .Name("mesh4d_pentatopes_produced_total")
                     .Help("Output pentatopes of succeeded jobs")
                     .Register(*registry_)
                     .Add({});
  received_ = &prometheus::BuildCounter()
                   .Name("mesh4d_received_bytes_total")
                   .Help("Label data accepted in uploads")
                   .Register(*registry_)
                   .Add({});
  sent_ = &prometheus::BuildCounter()
               .Name("mesh4d_sent_bytes_total")
               .Help("Mesh bytes sent in results")
               .Register(*registry_)
               .Add({});
  exposer_->RegisterCollectable(registry_);
}

int ServiceMetrics::port() const {
  const auto ports = exposer_->GetListeningPorts();
  return ports.empty() ? 0 : ports.front();
}

void ServiceMetrics::on_state(const v1::Job& job, v1::JobState previous) {
  if (previous >= v1::JOB_STATE_QUEUED && previous <= v1::JOB_STATE_CANCELLED)
    jobs_[previous]->Decrement();
  if (job.state() >= v1::JOB_STATE_QUEUED && job.state() <= v1::JOB_STATE_CANCELLED)
    jobs_[job.state()]->Increment();
  if (previous != v1::JOB_STATE_RUNNING) return;  // loaded jobs count in the gauges only
  if (job.state() >= v1::JOB_STATE_SUCCEEDED) finished_[job.state()]->Increment();
  if (job.state() != v1::JOB_STATE_SUCCEEDED) return;
  using google::protobuf::util::TimeUtil;
  duration_->Observe(TimeUtil::DurationToMilliseconds(job.finished() - job.started()) / 1000.0);
  const auto& i = job.stats().insertions();
  const std::uint64_t counts[5] = {i.r1(), i.r2(), i.r3(), i.r4(), i.r5()};
  for (int r = 0; r < 5; ++r) insertions_[r]->Increment(static_cast<double>(counts[r]));
  rollbacks_->Increment(static_cast<double>(job.progress().rollbacks()));
  pentatopes_->Increment(static_cast<double>(job.stats().pentatopes()));
}

void ServiceMetrics::on_bytes_received(std::uint64_t bytes) {
  received_->Increment(static_cast<double>(bytes));
}

void ServiceMetrics::on_bytes_sent(std::uint64_t bytes) {
  sent_->Increment(static_cast<double>(bytes));
}

}  // namespace mesh4d::server
