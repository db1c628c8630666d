#include "rest_api.h"

#include <CivetServer.h>
#include <google/protobuf/util/json_util.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "bearer_token.h"
#include "civetweb_tls.h"
#include "embedded_files.h"
#include "gzip_inflate.h"
#include "mesh/mesh_io.h"
#include "mesh/mesh_slice.h"
#include "mesh/slice_surface.h"
#include "mesh/vtu_writer.h"
#include "multipart_form.h"
#include "rest_upload.h"
#include "wire/digest.h"
#include "wire/service_error.h"

namespace mesh4d::server {
namespace {

// An error answered before or instead of the job service: HTTP status and gRPC code name.
struct HttpError {
  int status;
  const char* code;
  std::string message;
};

// The standard mapping of gRPC codes to HTTP statuses (google.rpc.Code), so that a REST error
// and a gRPC error of the same call say the same thing.
HttpError to_http(const wire::ServiceError& e) {
  switch (e.code()) {
    case wire::ErrorCode::invalid_argument:
      return {400, "INVALID_ARGUMENT", e.what()};
    case wire::ErrorCode::not_found:
      return {404, "NOT_FOUND", e.what()};
    case wire::ErrorCode::failed_precondition:
      return {400, "FAILED_PRECONDITION", e.what()};
    case wire::ErrorCode::cancelled:
      return {499, "CANCELLED", e.what()};
    case wire::ErrorCode::resource_exhausted:
      return {429, "RESOURCE_EXHAUSTED", e.what()};
    case wire::ErrorCode::internal:
      return {500, "INTERNAL", e.what()};
    case wire::ErrorCode::data_loss:
      return {500, "DATA_LOSS", e.what()};
    case wire::ErrorCode::already_exists:
      return {409, "ALREADY_EXISTS", e.what()};
  }
  return {500, "UNKNOWN", e.what()};
}

const char* reason(int status) {
  switch (status) {
    case 200:
      return "OK";
    case 201:
      return "Created";
    case 204:
      return "No Content";
    case 400:
      return "Bad Request";
    case 401:
      return "Unauthorized";
    case 403:
      return "Forbidden";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 408:
      return "Request Timeout";
    case 409:
      return "Conflict";
    case 429:
      return "Too Many Requests";
    case 499:
      return "Client Closed Request";
    default:
      return "Internal Server Error";
  }
}

void send(mg_connection* c, int status, const char* type, const std::string& body,
          const std::string& headers = "") {
  mg_printf(c,
            "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\n"
            "Cache-Control: no-store\r\n%s\r\n",
            status, reason(status), type, body.size(), headers.c_str());
  if (!body.empty()) mg_write(c, body.data(), body.size());
}

void send_error(mg_connection* c, const HttpError& e) {
  send(c, e.status, "application/json",
       nlohmann::json{{"code", e.code}, {"message", e.message}}.dump());
}

std::string to_json(const google::protobuf::Message& m) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string out;
  if (!google::protobuf::util::MessageToJsonString(m, &out, options).ok())
    throw std::runtime_error("cannot print a " + m.GetTypeName() + " as JSON");
  return out;
}

std::string url_decode(const std::string& s) {
  std::vector<char> out(s.size() + 1);
  const int n = mg_url_decode(s.c_str(), static_cast<int>(s.size()), out.data(),
                              static_cast<int>(out.size()), 1);
  return n < 0 ? s : std::string(out.data(), static_cast<std::size_t>(n));
}

std::map<std::string, std::string> query_of(const mg_request_info* ri) {
  std::map<std::string, std::string> query;
  if (!ri->query_string) return query;
  const std::string q = ri->query_string;
  for (std::size_t at = 0; at <= q.size();) {
    std::size_t end = q.find('&', at);
    if (end == std::string::npos) end = q.size();
    const std::string pair = q.substr(at, end - at);
    if (!pair.empty()) {
      const auto eq = pair.find('=');
      query[url_decode(pair.substr(0, eq))] =
          eq == std::string::npos ? "" : url_decode(pair.substr(eq + 1));
    }
    at = end + 1;
  }
  return query;
}

std::vector<std::string> split_path(const std::string& rest) {
  std::vector<std::string> parts;
  std::size_t at = 0;
  while (at < rest.size()) {
    std::size_t end = rest.find('/', at);
    if (end == std::string::npos) end = rest.size();
    if (end > at) parts.push_back(rest.substr(at, end - at));
    at = end + 1;
  }
  return parts;
}

// civetweb's worker threads have small stacks (ITK's readers and the slicer need more): heavy
// work runs on a thread of its own, with the default stack, while the worker waits.
template <typename F>
auto on_full_stack(F&& work) {
  return std::async(std::launch::async, std::forward<F>(work)).get();
}

const char* event_name(const v1::JobEvent& e) {
  switch (e.event_case()) {
    case v1::JobEvent::kSnapshot:
      return "snapshot";
    case v1::JobEvent::kState:
      return "state";
    case v1::JobEvent::kProgress:
      return "progress";
    case v1::JobEvent::kFinished:
      return "finished";
    default:
      return "event";
  }
}

}  // namespace

// The dashboard's session cookie (POST /v1/login): the token itself, HttpOnly.
constexpr const char* kSessionCookie = "mesh4d_token";

// Event streams open at once: each holds one of civetweb's workers for as long as it lasts.
constexpr std::size_t kMaxEventStreams = 128;

class RestApi::Handler : public CivetHandler {
 public:
  Handler(JobManager& jobs, std::string token, std::uint64_t max_body, JobObserver* observer)
      : jobs_(jobs), token_(std::move(token)), max_body_(max_body), observer_(observer) {}

  bool handleGet(CivetServer*, mg_connection* c) override { return serve(c, "GET"); }
  bool handlePost(CivetServer*, mg_connection* c) override { return serve(c, "POST"); }
  bool handleDelete(CivetServer*, mg_connection* c) override { return serve(c, "DELETE"); }
  bool handlePut(CivetServer*, mg_connection* c) override { return serve(c, "PUT"); }

 private:
  bool serve(mg_connection* c, const std::string& method) {
    const mg_request_info* ri = mg_get_request_info(c);
    const std::string uri = ri->local_uri ? ri->local_uri : "/";
    const auto query = query_of(ri);
    try {
      route(c, method, uri, query);
    } catch (const wire::ServiceError& e) {
      send_error(c, to_http(e));
    } catch (const HttpError& e) {
      send_error(c, e);
    } catch (const std::exception& e) {
      spdlog::error("REST {} {}: {}", method, uri, e.what());
      send_error(c, {500, "INTERNAL", e.what()});
    }
    return true;
  }

  void route(mg_connection* c, const std::string& method, const std::string& uri,
             const std::map<std::string, std::string>& query) {
    if (uri == "/" || uri == "/index.html") {
      require(method, "GET");
      send(c, 200, "text/html; charset=utf-8", embedded::dashboard_html());
      return;
    }
    if (uri == "/viewer.js") {
      require(method, "GET");
      return viewer(c);
    }
    if (uri == "/openapi.yaml") {
      require(method, "GET");
      send(c, 200, "application/yaml", embedded::openapi_yaml());
      return;
    }
    if (uri == "/v1/login") {
      require(method, "POST");
      return login(c);
    }
    if (uri != "/v1/jobs" && uri.rfind("/v1/jobs/", 0) != 0)
      throw HttpError{404, "NOT_FOUND", "no such path: " + uri + " (the API is under /v1/jobs)"};
    authorize(c, query);
    const auto parts = split_path(uri.substr(std::string("/v1/jobs").size()));
    if (parts.empty()) {
      if (method == "GET") return list(c, query);
      require(method, "POST");
      return submit(c, query);
    }
    const std::string& id = parts[0];
    if (parts.size() == 1) {
      if (method == "GET") return send(c, 200, "application/json", to_json(jobs_.get(id)));
      require(method, "DELETE");
      jobs_.remove(id);
      return send(c, 204, "application/json", "");
    }
    if (parts.size() == 2 && parts[1] == "cancel") {
      require(method, "POST");
      return send(c, 200, "application/json", to_json(jobs_.cancel(id)));
    }
    if (parts.size() == 2 && parts[1] == "events") {
      require(method, "GET");
      return events(c, id);
    }
    if (parts.size() == 2 && parts[1] == "mesh") {
      require(method, "GET");
      return mesh(c, id);
    }
    if (parts.size() == 3 && parts[1] == "slices") {
      require(method, "GET");
      return slice(c, id, parts[2], query);
    }
    throw HttpError{404, "NOT_FOUND", "no such path: " + uri};
  }

  // The viewer's bundle as stored (gzip), or inflated for a client that does not accept gzip.
  static void viewer(mg_connection* c) {
    const char* accepted = mg_get_header(c, "Accept-Encoding");
    const std::string_view gz = embedded::viewer_js_gzip();
    if (accepted && std::string_view(accepted).find("gzip") != std::string_view::npos)
      send(c, 200, "text/javascript; charset=utf-8", std::string(gz),
           "Content-Encoding: gzip\r\nVary: Accept-Encoding\r\n");
    else
      send(c, 200, "text/javascript; charset=utf-8", inflate_gzip(gz), "Vary: Accept-Encoding\r\n");
  }

  static void require(const std::string& method, const char* allowed) {
    if (method != allowed)
      throw HttpError{405, "UNIMPLEMENTED",
                      method + " is not supported here (use " + allowed + ")"};
  }

  // The dashboard's sign-in: a valid token (JSON {"token": ...}) becomes a cookie that scripts
  // cannot read (HttpOnly) and other sites cannot send (SameSite=Strict), so that the page
  // never puts the token in a URL and its event streams (EventSource sets no headers) still
  // authenticate.
  void login(mg_connection* c) const {
    std::string body;
    read_body(c, body, 4096);
    const auto json = nlohmann::json::parse(body, nullptr, false);
    if (!json.is_object() || !json.contains("token") || !json["token"].is_string())
      throw HttpError{400, "INVALID_ARGUMENT", "send {\"token\": \"...\"}"};
    const std::string token = json["token"];
    if (!token_.empty() && token != token_)
      throw HttpError{403, "PERMISSION_DENIED", "the token is not valid for this server"};
    send(c, 204, "application/json", "",
         "Set-Cookie: " + std::string(kSessionCookie) + "=" + token +
             "; HttpOnly; SameSite=Strict; Path=/" + (civetweb_tls_enabled() ? "; Secure" : "") +
             "\r\n");
  }

  void authorize(mg_connection* c, const std::map<std::string, std::string>& query) const {
    if (token_.empty()) return;
    const char* header = mg_get_header(c, "Authorization");
    std::string presented;
    char cookie[512];
    if (header)
      presented = header;
    else if (const char* cookies = mg_get_header(c, "Cookie");
             cookies && mg_get_cookie(cookies, kSessionCookie, cookie, sizeof cookie) > 0)
      presented = std::string("Bearer ") + cookie;
    else if (const auto it = query.find("access_token"); it != query.end())
      presented = "Bearer " + it->second;  // for EventSource clients outside the dashboard
    if (presented.empty())
      throw HttpError{401, "UNAUTHENTICATED",
                      "this server requires a token: send 'Authorization: Bearer <token>'"};
    if (!bearer_token_matches(presented, token_))
      throw HttpError{403, "PERMISSION_DENIED", "the token is not valid for this server"};
  }

  void list(mg_connection* c, const std::map<std::string, std::string>& query) {
    v1::JobState state = v1::JOB_STATE_UNSPECIFIED;
    if (const auto it = query.find("state"); it != query.end() && !it->second.empty()) {
      std::string upper = it->second;
      for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      if (upper.rfind("JOB_STATE_", 0) != 0) upper = "JOB_STATE_" + upper;
      if (!v1::JobState_Parse(upper, &state))
        throw wire::ServiceError(
            wire::ErrorCode::invalid_argument,
            "unknown state '" + it->second + "' (queued, running, succeeded, failed, cancelled)");
    }
    std::uint32_t page_size = 0;
    if (const auto it = query.find("page_size"); it != query.end()) {
      char* end = nullptr;
      const unsigned long n = std::strtoul(it->second.c_str(), &end, 10);
      if (it->second.empty() || *end != '\0' || n > 100000)
        throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                                 "page_size '" + it->second + "' is not a count up to 100000");
      page_size = static_cast<std::uint32_t>(n);
    }
    const auto token = query.count("page_token") ? query.at("page_token") : std::string();
    auto page = jobs_.list(state, page_size, token);
    v1::ListJobsResponse response;
    for (auto& job : page.jobs) *response.add_jobs() = std::move(job);
    response.set_next_page_token(page.next_token);
    send(c, 200, "application/json", to_json(response));
  }

  void submit(mg_connection* c, const std::map<std::string, std::string>& query) {
    const mg_request_info* ri = mg_get_request_info(c);
    if (ri->content_length > 0 && static_cast<std::uint64_t>(ri->content_length) > max_body_)
      throw wire::ServiceError(wire::ErrorCode::resource_exhausted,
                               "the upload (" + std::to_string(ri->content_length) +
                                   " bytes) is over the server's limit of " +
                                   std::to_string(max_body_));
    const char* type = mg_get_header(c, "Content-Type");
    Form form;
    auto fields = query;
    if (type && std::string(type).rfind("multipart/form-data", 0) == 0) {
      read_form(c, form);
      for (const auto& [key, value] : form.fields) fields.emplace(key, value);  // query wins
    } else {
      read_body(c, form.image);
    }
    if (observer_) observer_->on_bytes_received(form.image.size());
    const auto submitted = on_full_stack([&] {
      RestUpload upload =
          decode_rest_upload(form.image, fields, form.params, jobs_.max_image_bytes());
      return jobs_.submit(upload.spec, std::move(upload.data));
    });
    v1::SubmitJobResponse response;
    *response.mutable_job() = submitted.job;
    response.set_deduplicated(submitted.deduplicated);
    send(c, submitted.deduplicated ? 200 : 201, "application/json", to_json(response),
         "Location: /v1/jobs/" + submitted.job.id() + "\r\n");
  }

  // A submission as parts: "image" (the file), "params" (a JSON object), other parts as query
  // keys (name, request_id, time_scale, ...).
  struct Form {
    std::string image, params;
    std::map<std::string, std::string> fields;
  };

  // The request body, up to `limit` bytes (0: the upload limit).
  void read_body(mg_connection* c, std::string& body, std::uint64_t limit = 0) const {
    if (limit == 0) limit = max_body_;
    const mg_request_info* ri = mg_get_request_info(c);
    if (ri->content_length > 0 && static_cast<std::uint64_t>(ri->content_length) <= limit)
      body.reserve(static_cast<std::size_t>(ri->content_length));
    std::vector<char> buffer(1 << 16);
    for (int n; (n = mg_read(c, buffer.data(), buffer.size())) > 0;) {
      body.append(buffer.data(), static_cast<std::size_t>(n));
      if (body.size() > limit) throw too_big();
    }
  }

  void read_form(mg_connection* c, Form& form) const {
    std::string body;
    read_body(c, body);
    const char* type = mg_get_header(c, "Content-Type");
    for (FormPart& part : parse_multipart(type ? type : "", body)) {
      if (part.name == "image") {
        form.image = std::move(part.body);
        continue;
      }
      if (part.body.size() > (1u << 20))
        throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                                 "the multipart part \"" + part.name + "\" is over 1 MiB");
      (part.name == "params" ? form.params : form.fields[part.name]) = std::move(part.body);
    }
    if (form.image.empty())
      throw wire::ServiceError(
          wire::ErrorCode::invalid_argument,
          "a multipart submission needs an \"image\" part (curl -F image=@FILE)");
  }

  wire::ServiceError too_big() const {
    return wire::ServiceError(
        wire::ErrorCode::resource_exhausted,
        "the upload is over the server's limit of " + std::to_string(max_body_) + " bytes");
  }

  // Server-Sent Events: the same events as WatchJob, one per message ("event:" its kind,
  // "id:" its sequence, "data:" the JobEvent as JSON), until the job ends. A reconnecting
  // EventSource sends Last-Event-ID and gets the events after it.
  void events(mg_connection* c, const std::string& id) {
    // Each stream holds a worker until its job ends: past the cap, clients poll instead.
    struct Admission {
      std::atomic<std::size_t>& open;
      ~Admission() { --open; }
    } admission{open_streams_};
    if (++open_streams_ > kMaxEventStreams)
      throw wire::ServiceError(wire::ErrorCode::resource_exhausted,
                               "too many event streams are open (" +
                                   std::to_string(kMaxEventStreams) + "); poll GET /v1/jobs/" + id +
                                   " instead, or retry later");
    std::uint64_t after = 0;
    if (const char* last = mg_get_header(c, "Last-Event-ID")) {
      char* end = nullptr;
      const unsigned long long n = std::strtoull(last, &end, 10);
      if (end != last && *end == '\0') after = n;
    }
    // Chunked, so that the stream has an end the client sees and the connection can be kept
    // alive after it.
    bool started = false;
    int quiet = 0;  // half-second waits without an event
    const auto chunk = [&](const std::string& text) {
      return mg_send_chunk(c, text.data(), static_cast<unsigned>(text.size())) > 0;
    };
    const auto write = [&](const v1::JobEvent& e) {
      if (!started) {  // an unknown id threw before this: a plain 404
        mg_printf(c,
                  "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\n"
                  "Cache-Control: no-store\r\nTransfer-Encoding: chunked\r\n\r\n");
        started = true;
      }
      quiet = 0;
      return chunk("event: " + std::string(event_name(e)) +
                   "\nid: " + std::to_string(e.sequence()) + "\ndata: " + to_json(e) + "\n\n");
    };
    // A comment every second finds a reader that left while nothing happened, and frees its
    // worker.
    const auto reader_left = [&] {
      if (++quiet < 2) return false;
      quiet = 0;
      return !chunk(":\n\n");
    };
    const auto end = jobs_.watch(id, after, write, reader_left);
    if (end == JobManager::WatchEnd::job_deleted)
      chunk("event: error\ndata: " +
            nlohmann::json{{"code", "NOT_FOUND"}, {"message", "the job was deleted"}}.dump() +
            "\n\n");
    if (end == JobManager::WatchEnd::server_stopping)
      chunk("event: error\ndata: " +
            nlohmann::json{{"code", "UNAVAILABLE"},
                           {"message", "the server is shutting down; reconnect once it is back"}}
                .dump() +
            "\n\n");
    if (started && end != JobManager::WatchEnd::watcher_left) mg_send_chunk(c, "", 0);
  }

  void mesh(mg_connection* c, const std::string& id) {
    const auto result = jobs_.result(id);
    const std::string digest = wire::sha256_hex(result.mesh);  // checked against the job's
    send(c, 200, "application/octet-stream", result.mesh,
         "Content-Disposition: attachment; filename=\"" + id +
             ".m4d\"\r\nX-Mesh4d-SHA256: " + digest + "\r\n");
    if (observer_) observer_->on_bytes_sent(result.mesh.size());
  }

  // A time slice: as VTK's .vtu (the whole section, or its boundary with ?boundary=1), or its
  // boundary as .surface, the compact binary form the dashboard's viewer draws
  // (mesh/slice_surface.h).
  void slice(mg_connection* c, const std::string& id, const std::string& file,
             const std::map<std::string, std::string>& query) {
    const auto dot = file.rfind('.');
    const std::string format = dot == std::string::npos ? "" : file.substr(dot + 1);
    if (format != "vtu" && format != "surface")
      throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                               "a slice is named by its time and format: /slices/{t}.vtu or "
                               "/slices/{t}.surface, not " +
                                   file);
    const std::string t_text = file.substr(0, dot);
    char* end = nullptr;
    const double t = std::strtod(t_text.c_str(), &end);
    if (t_text.empty() || *end != '\0' || !std::isfinite(t))
      throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                               "slice time '" + t_text + "' is not a number");
    const bool surface = format == "surface";
    const bool boundary = surface || (query.count("boundary") && query.at("boundary") != "0");
    const std::string body = on_full_stack([&] {
      const auto result = jobs_.result(id);
      const mesh::Mesh4 m = mesh::decode_m4d(
          reinterpret_cast<const std::uint8_t*>(result.mesh.data()), result.mesh.size());
      const mesh::SliceMesh s = mesh::slice_mesh(m, t, boundary);
      if (surface) return mesh::encode_slice_surface(m, s);
      return boundary ? mesh::slice_boundary_vtu(s) : mesh::slice_vtu(m, s);
    });
    send(c, 200, surface ? "application/octet-stream" : "application/xml", body);
  }

  JobManager& jobs_;
  const std::string token_;
  const std::uint64_t max_body_;
  JobObserver* observer_;
  std::atomic<std::size_t> open_streams_{0};
};

namespace {

// civetweb's own errors (a malformed request line, headers too long, a timeout) in the API's
// JSON form.
int json_http_error(mg_connection* c, int status, const char* message) {
  send_error(c, {status, status == 408 ? "DEADLINE_EXCEEDED" : "INVALID_ARGUMENT",
                 message ? message : "bad request"});
  return 0;
}

}  // namespace

RestApi::RestApi(JobManager& jobs, const std::string& listen, std::string token,
                 std::uint64_t max_body_bytes, JobObserver* observer)
    : handler_(std::make_unique<Handler>(jobs, std::move(token), max_body_bytes, observer)) {
  // One worker per open connection (civetweb's model): the pool is large enough for every event
  // stream the handler admits (kMaxEventStreams) and as many other clients again, and a client
  // that sends its request slowly, or sits idle on a kept-alive connection, loses its worker
  // after the timeouts.
  const std::vector<std::string> options = {
      "listening_ports",       civetweb_listening_port(listen),
      "num_threads",           std::to_string(2 * kMaxEventStreams),
      "enable_keep_alive",     "yes",
      "keep_alive_timeout_ms", "1000",
      "request_timeout_ms",    "10000"};
  static const CivetCallbacks callbacks = [] {
    CivetCallbacks c;
    c.http_error = json_http_error;
    add_tls_setup(c);
    return c;
  }();
  try {
    server_ = std::make_unique<CivetServer>(options, &callbacks);
  } catch (const CivetException& e) {
    throw std::runtime_error(std::string("cannot serve HTTP on ") + listen + ": " + e.what());
  }
  server_->addHandler("/", *handler_);
}

RestApi::~RestApi() {
  if (server_) server_->close();  // stops the workers before the handler goes
}

int RestApi::port() const {
  const auto ports = server_->getListeningPorts();
  return ports.empty() ? 0 : ports.front();
}

}  // namespace mesh4d::server
