#include "wire/submit_stream.h"

#include <algorithm>
#include <string>

namespace mesh4d::wire {

grpc::Status submit_job(v1::MeshService::Stub& stub, grpc::ClientContext& context,
                        const v1::JobSpec& spec, std::string_view data,
                        v1::SubmitJobResponse* response, std::size_t chunk) {
  auto writer = stub.SubmitJob(&context, response);
  v1::SubmitJobRequest message;
  *message.mutable_spec() = spec;
  bool sent = writer->Write(message);
  chunk = std::max<std::size_t>(chunk, 1);
  for (std::size_t at = 0; sent && at < data.size(); at += chunk) {
    message.Clear();
    message.set_chunk(std::string(data.substr(at, chunk)));
    sent = writer->Write(message);
  }
  writer->WritesDone();
  return writer->Finish();
}

}  // namespace mesh4d::wire
