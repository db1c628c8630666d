// The server's log lines: by default one JSON object per line for log shippers,
//   {"time":"2026-11-23T10:00:00.123Z","level":"info","job":"j…","msg":"running"}
// or plain text for people at a terminal. A line logged for a job carries its id as a field,
// not inside the message, so a pipeline can filter on it.
#pragma once

#include <spdlog/spdlog.h>

#include <string>

namespace mesh4d::server {

enum class LogFormat { json, text };

/// Parses "json" or "text"; throws std::invalid_argument otherwise.
LogFormat parse_log_format(const std::string& name);

/// Installs the format on spdlog's default logger (stderr).
void configure_logging(LogFormat format);

/// While alive, log lines written by this thread carry `job_id`. Nests.
class JobLogScope {
 public:
  explicit JobLogScope(const std::string& job_id);
  ~JobLogScope();
  JobLogScope(const JobLogScope&) = delete;
  JobLogScope& operator=(const JobLogScope&) = delete;

 private:
  const std::string* previous_;
};

/// One log line about one job.
template <typename... Args>
void log_job(spdlog::level::level_enum level, const std::string& job_id,
             spdlog::format_string_t<Args...> format, Args&&... args) {
  JobLogScope scope(job_id);
  spdlog::log(level, format, std::forward<Args>(args)...);
}

}  // namespace mesh4d::server
