// Prometheus metrics of the service (prometheus-cpp, served on its own HTTP port at /metrics):
// jobs by state, queue depth, job durations, insertions per rule, rollbacks, pentatopes
// produced, bytes received and sent. Fed by the JobManager through JobObserver.
#pragma once

#include <prometheus/counter.h>
#include <prometheus/exposer.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>

#include <array>
#include <memory>
#include <string>

#include "job_manager.h"

namespace mesh4d::server {

class ServiceMetrics : public JobObserver {
 public:
  /// Serves /metrics on `listen` (host:port; port 0 picks one). Throws when it cannot bind.
  explicit ServiceMetrics(const std::string& listen);
  int port() const;

  void on_state(const v1::Job& job, v1::JobState previous) override;
  void on_bytes_received(std::uint64_t bytes) override;
  void on_bytes_sent(std::uint64_t bytes) override;

 private:
  std::shared_ptr<prometheus::Registry> registry_;
  std::unique_ptr<prometheus::Exposer> exposer_;
  std::array<prometheus::Gauge*, 6> jobs_{};  // by JobState
  prometheus::Counter* finished_[6]{};
  prometheus::Histogram* duration_ = nullptr;
  std::array<prometheus::Counter*, 5> insertions_{};
  prometheus::Counter* rollbacks_ = nullptr;
  prometheus::Counter* pentatopes_ = nullptr;
  prometheus::Counter* received_ = nullptr;
  prometheus::Counter* sent_ = nullptr;
};

}  // namespace mesh4d::server
