#include "mesh_service.h"

#include <spdlog/spdlog.h>

#include <chrono>

#include "bearer_token.h"
#include "mesh/mesh_io.h"
#include "wire/digest.h"
#include "wire/service_error.h"
#include "wire/upload_codec.h"

namespace mesh4d::server {
namespace {

constexpr std::size_t kResultChunk = 1 << 20;

grpc::Status to_status(const wire::ServiceError& e) {
  switch (e.code()) {
    case wire::ErrorCode::invalid_argument:
      return {grpc::StatusCode::INVALID_ARGUMENT, e.what()};
    case wire::ErrorCode::not_found:
      return {grpc::StatusCode::NOT_FOUND, e.what()};
    case wire::ErrorCode::failed_precondition:
      return {grpc::StatusCode::FAILED_PRECONDITION, e.what()};
    case wire::ErrorCode::cancelled:
      return {grpc::StatusCode::CANCELLED, e.what()};
    case wire::ErrorCode::resource_exhausted:
      return {grpc::StatusCode::RESOURCE_EXHAUSTED, e.what()};
    case wire::ErrorCode::internal:
      return {grpc::StatusCode::INTERNAL, e.what()};
    case wire::ErrorCode::data_loss:
      return {grpc::StatusCode::DATA_LOSS, e.what()};
    case wire::ErrorCode::already_exists:
      return {grpc::StatusCode::ALREADY_EXISTS, e.what()};
  }
  return {grpc::StatusCode::UNKNOWN, e.what()};
}

// Runs a handler body, turning the service's errors into statuses.
template <typename F>
grpc::Status guarded(F&& body) {
  try {
    return body();
  } catch (const wire::ServiceError& e) {
    return to_status(e);
  } catch (const std::exception& e) {
    spdlog::error("internal error: {}", e.what());
    return {grpc::StatusCode::INTERNAL, e.what()};
  }
}

}  // namespace

grpc::Status MeshService::authorize(const grpc::ServerContext* context) const {
  if (token_.empty()) return grpc::Status::OK;
  const auto& metadata = context->client_metadata();
  const auto it = metadata.find("authorization");
  if (it == metadata.end())
    return {grpc::StatusCode::UNAUTHENTICATED,
            "this server requires a token: send 'authorization: Bearer <token>'"};
  const std::string value(it->second.data(), it->second.size());
  if (!bearer_token_matches(value, token_))
    return {grpc::StatusCode::PERMISSION_DENIED, "the token is not valid for this server"};
  return grpc::Status::OK;
}

grpc::Status MeshService::SubmitJob(grpc::ServerContext* context,
                                    grpc::ServerReader<v1::SubmitJobRequest>* reader,
                                    v1::SubmitJobResponse* response) {
  if (auto s = authorize(context); !s.ok()) return s;
  return guarded([&] {
    v1::SubmitJobRequest message;
    if (!reader->Read(&message) || !message.has_spec())
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "the first message of SubmitJob must carry the job spec");
    const v1::JobSpec spec = message.spec();
    // The header is checked before the data is read: a bad or oversized upload is refused at
    // once instead of after gigabytes.
    if (!spec.has_image())
      throw wire::ServiceError(wire::ErrorCode::invalid_argument, "spec.image is missing");
    const std::uint64_t expected = wire::check_header(spec.image());
    std::string data;
    while (reader->Read(&message)) {
      if (message.has_spec())
        throw wire::ServiceError(wire::ErrorCode::invalid_argument, "the job spec was sent twice");
      if (data.size() + message.chunk().size() > expected)
        throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                                 "more label data than image.byte_size announced (" +
                                     std::to_string(expected) + " bytes)");
      if (data.empty()) data.reserve(expected);
      data += message.chunk();
    }
    if (context->IsCancelled())
      return grpc::Status(grpc::StatusCode::CANCELLED, "the upload was cancelled");
    const auto submitted = jobs_.submit(spec, std::move(data));
    *response->mutable_job() = submitted.job;
    response->set_deduplicated(submitted.deduplicated);
    return grpc::Status::OK;
  });
}

grpc::Status MeshService::GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                                 v1::Job* response) {
  if (auto s = authorize(context); !s.ok()) return s;
  return guarded([&] {
    *response = jobs_.get(request->job_id());
    return grpc::Status::OK;
  });
}

grpc::Status MeshService::WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                                   grpc::ServerWriter<v1::JobEvent>* writer) {
  if (auto s = authorize(context); !s.ok()) return s;
  return guarded([&] {
    // The current state first, then every event after it until the job ends.
    switch (jobs_.watch(
        request->job_id(), 0, [&](const v1::JobEvent& e) { return writer->Write(e); },
        [&] { return context->IsCancelled(); })) {
      case JobManager::WatchEnd::job_ended:
        return grpc::Status::OK;
      case JobManager::WatchEnd::job_deleted:
        return grpc::Status(grpc::StatusCode::NOT_FOUND, "the job was deleted");
      case JobManager::WatchEnd::server_stopping:
        return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                            "the server is shutting down; watch again once it is back");
      case JobManager::WatchEnd::watcher_left:
        break;
    }
    return grpc::Status(grpc::StatusCode::CANCELLED, "the watcher went away");
  });
}

grpc::Status MeshService::CancelJob(grpc::ServerContext* context,
                                    const v1::CancelJobRequest* request, v1::Job* response) {
  if (auto s = authorize(context); !s.ok()) return s;
  return guarded([&] {
    *response = jobs_.cancel(request->job_id());
    return grpc::Status::OK;
  });
}

grpc::Status MeshService::ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                                   v1::ListJobsResponse* response) {
  if (auto s = authorize(context); !s.ok()) return s;
  return guarded([&] {
    auto page = jobs_.list(request->state(), request->page_size(), request->page_token());
    for (auto& job : page.jobs) *response->add_jobs() = std::move(job);
    response->set_next_page_token(page.next_token);
    return grpc::Status::OK;
  });
}

grpc::Status MeshService::GetResult(grpc::ServerContext* context,
                                    const v1::GetResultRequest* request,
                                    grpc::ServerWriter<v1::GetResultResponse>* writer) {
  if (auto s = authorize(context); !s.ok()) return s;
  return guarded([&] {
    const auto result = jobs_.result(request->job_id());
    v1::GetResultResponse message;
    auto* header = message.mutable_header();
    *header->mutable_stats() = result.job.stats();
    for (const auto& w : result.job.warnings()) header->add_warnings(w);
    header->set_byte_size(result.mesh.size());
    header->set_sha256(result.job.result_sha256());  // what result() checked the mesh against
    if (!writer->Write(message)) return grpc::Status(grpc::StatusCode::CANCELLED, "reader left");
    for (std::size_t at = 0; at < result.mesh.size(); at += kResultChunk) {
      message.Clear();
      message.set_chunk(result.mesh.substr(at, kResultChunk));
      if (!writer->Write(message)) return grpc::Status(grpc::StatusCode::CANCELLED, "reader left");
    }
    if (observer_) observer_->on_bytes_sent(result.mesh.size());
    return grpc::Status::OK;
  });
}

grpc::Status MeshService::DeleteJob(grpc::ServerContext* context,
                                    const v1::DeleteJobRequest* request,
                                    v1::DeleteJobResponse* /*response*/) {
  if (auto s = authorize(context); !s.ok()) return s;
  return guarded([&] {
    jobs_.remove(request->job_id());
    return grpc::Status::OK;
  });
}

}  // namespace mesh4d::server
