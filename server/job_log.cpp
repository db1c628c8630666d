#include "job_log.h"

#include <spdlog/formatter.h>
#include <spdlog/sinks/stdout_sinks.h>

#include <ctime>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace mesh4d::server {
namespace {

// The job of the log call in progress on this thread: spdlog's default logger is synchronous,
// so its formatter runs on the calling thread and can read it.
thread_local const std::string* current_job = nullptr;

// "2026-11-23T10:00:00.123Z": UTC with milliseconds, what log shippers parse without help.
std::string utc_time(spdlog::log_clock::time_point time) {
  const auto since_epoch = time.time_since_epoch();
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch);
  const auto millis = std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch - seconds);
  const std::time_t t = seconds.count();
  std::tm utc{};
  gmtime_r(&t, &utc);
  char text[32];
  const std::size_t n = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  return fmt::format("{}.{:03d}Z", std::string_view(text, n), static_cast<int>(millis.count()));
}

class LineFormatter final : public spdlog::formatter {
 public:
  explicit LineFormatter(LogFormat format) : format_(format) {}

  void format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) override {
    const auto level_view = spdlog::level::to_string_view(msg.level);
    const std::string_view level(level_view.data(), level_view.size());
    const std::string_view text(msg.payload.data(), msg.payload.size());
    std::string line;
    if (format_ == LogFormat::json) {
      nlohmann::ordered_json j;
      j["time"] = utc_time(msg.time);
      j["level"] = level;
      if (current_job) j["job"] = *current_job;
      j["msg"] = text;
      // Invalid UTF-8 in a message (a file name, say) is replaced, never a broken line.
      line = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    } else {
      line = current_job
                 ? fmt::format("{} {} job {}: {}", utc_time(msg.time), level, *current_job, text)
                 : fmt::format("{} {} {}", utc_time(msg.time), level, text);
    }
    line += '\n';
    dest.append(line.data(), line.data() + line.size());
  }

  std::unique_ptr<spdlog::formatter> clone() const override {
    return std::make_unique<LineFormatter>(format_);
  }

 private:
  LogFormat format_;
};

}  // namespace

LogFormat parse_log_format(const std::string& name) {
  if (name == "json") return LogFormat::json;
  if (name == "text") return LogFormat::text;
  throw std::invalid_argument("log format '" + name + "' is neither json nor text");
}

void configure_logging(LogFormat format) {
  // stderr, unbuffered, as before; the formatter decides the line.
  auto logger =
      std::make_shared<spdlog::logger>("mesh4d", std::make_shared<spdlog::sinks::stderr_sink_mt>());
  logger->set_formatter(std::make_unique<LineFormatter>(format));
  spdlog::set_default_logger(logger);
}

JobLogScope::JobLogScope(const std::string& job_id) : previous_(current_job) {
  current_job = &job_id;
}

JobLogScope::~JobLogScope() {
  current_job = previous_;
}

}  // namespace mesh4d::server
