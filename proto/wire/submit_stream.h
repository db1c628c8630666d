// SubmitJob's client side: the spec first, then the data in chunks, then the server's answer.
#pragma once

#include <grpcpp/grpcpp.h>

#include <cstddef>
#include <string_view>

#include "mesh4d/v1/mesh4d.grpc.pb.h"

namespace mesh4d::wire {

/// The chunk size the client sends: well under gRPC's default 4 MiB message limit.
inline constexpr std::size_t kUploadChunk = std::size_t{1} << 20;

/// Streams `spec` and `data` (at most `chunk` bytes a message) on `context` and returns the
/// call's status; `response` holds the job when it is OK. A write the server refused ends the
/// stream early: the status then says why.
grpc::Status submit_job(v1::MeshService::Stub& stub, grpc::ClientContext& context,
                        const v1::JobSpec& spec, std::string_view data,
                        v1::SubmitJobResponse* response, std::size_t chunk = kUploadChunk);

}  // namespace mesh4d::wire
