#include "server_options.h"

#include <CLI/CLI.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace mesh4d::server {

void load_config_file(const std::string& path, ServerOptions& o) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read the configuration file " + path);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("configuration file " + path + " is not JSON: " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error("configuration file " + path + ": not an object");
  for (const auto& [key, value] : j.items()) {
    try {
      if (key == "listen")
        o.listen = value.get<std::string>();
      else if (key == "port_file")
        o.port_file = value.get<std::string>();
      else if (key == "data_dir")
        o.data_dir = value.get<std::string>();
      else if (key == "running_jobs")
        o.running_jobs = value.get<unsigned>();
      else if (key == "threads_per_job")
        o.threads_per_job = value.get<unsigned>();
      else if (key == "max_queued_jobs")
        o.max_queued_jobs = value.get<unsigned>();
      else if (key == "max_image_mb")
        o.max_image_mb = value.get<std::uint64_t>();
      else if (key == "max_vertex_budget")
        o.max_vertex_budget = value.get<std::uint64_t>();
      else if (key == "retention_hours")
        o.retention_hours = value.get<double>();
      else if (key == "token")
        o.token = value.get<std::string>();
      else if (key == "tls_cert")
        o.tls_cert = value.get<std::string>();
      else if (key == "tls_key")
        o.tls_key = value.get<std::string>();
      else if (key == "metrics_listen")
        o.metrics_listen = value.get<std::string>();
      else if (key == "http_listen")
        o.http_listen = value.get<std::string>();
      else if (key == "log_format")
        o.log_format = value.get<std::string>();
      else
        throw std::runtime_error("unknown key");
    } catch (const std::exception& e) {
      throw std::runtime_error("configuration file " + path + ", key '" + key + "': " + e.what());
    }
  }
}

void add_server_options(CLI::App& app, ServerOptions& o) {
  app.add_option("--config", "a JSON file of these options (keys: the flags with '_' for '-')")
      ->envname("MESH4D_CONFIG");
  app.add_option("--listen", o.listen, "gRPC address host:port (port 0: any free port)")
      ->envname("MESH4D_LISTEN")
      ->capture_default_str();
  app.add_option("--port-file", o.port_file, "write the bound gRPC port to this file once serving")
      ->envname("MESH4D_PORT_FILE");
  app.add_option("--data-dir", o.data_dir, "where jobs, inputs and results are kept")
      ->envname("MESH4D_DATA_DIR")
      ->capture_default_str();
  app.add_option("--running-jobs", o.running_jobs,
                 "most jobs refined at once (0: one per core; the cores are shared among them)")
      ->envname("MESH4D_RUNNING_JOBS")
      ->check(CLI::Range(0u, 256u))
      ->capture_default_str();
  app.add_option("--threads-per-job", o.threads_per_job,
                 "most threads a job uses (0: every core, for a job alone)")
      ->envname("MESH4D_THREADS_PER_JOB")
      ->capture_default_str();
  app.add_option("--max-queued-jobs", o.max_queued_jobs, "queued jobs beyond this are refused")
      ->envname("MESH4D_MAX_QUEUED_JOBS")
      ->check(CLI::Range(1u, 1000000u))
      ->capture_default_str();
  app.add_option("--max-image-mb", o.max_image_mb, "largest accepted upload, in MiB")
      ->envname("MESH4D_MAX_IMAGE_MB")
      ->capture_default_str();
  app.add_option("--max-vertex-budget", o.max_vertex_budget, "largest vertex budget a job may ask")
      ->envname("MESH4D_MAX_VERTEX_BUDGET")
      ->capture_default_str();
  app.add_option("--retention-hours", o.retention_hours,
                 "finished jobs are deleted after this many hours (0: kept)")
      ->envname("MESH4D_RETENTION_HOURS")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--token", o.token, "require 'authorization: Bearer TOKEN' on every call")
      ->envname("MESH4D_TOKEN");
  app.add_option("--tls-cert", o.tls_cert, "PEM certificate chain (with --tls-key: TLS on)")
      ->envname("MESH4D_TLS_CERT");
  app.add_option("--tls-key", o.tls_key, "PEM private key")->envname("MESH4D_TLS_KEY");
  app.add_option("--metrics-listen", o.metrics_listen,
                 "host:port of the Prometheus /metrics endpoint (empty: off; port 0: any)")
      ->envname("MESH4D_METRICS_LISTEN")
      ->capture_default_str();
  app.add_option("--http-listen", o.http_listen,
                 "host:port of the REST/JSON API and the dashboard (empty: off; port 0: any)")
      ->envname("MESH4D_HTTP_LISTEN")
      ->capture_default_str();
  app.add_option("--log-format", o.log_format, "json (one object a line, with job ids) or text")
      ->envname("MESH4D_LOG_FORMAT")
      ->check(CLI::IsMember({"json", "text"}))
      ->capture_default_str();
}

}  // namespace mesh4d::server
