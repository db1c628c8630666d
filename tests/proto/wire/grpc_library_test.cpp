#include "wire/grpc_library.h"

#include <grpc/grpc.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include "mesh4d/v1/mesh4d.grpc.pb.h"

namespace mesh4d::wire {
namespace {

// When the program's hold ends, gRPC has cleaned up: nothing of it runs on while main returns,
// even after a channel that made a call (its connection attempt ends on gRPC's own threads).
TEST(GrpcLibrary, GrpcIsCleanedUpWhenTheHoldEnds) {
  {
    const GrpcLibrary library;
    {
      // A port nothing listens on (the loopback's port 1): the call fails at once.
      auto stub = v1::MeshService::NewStub(
          grpc::CreateChannel("127.0.0.1:1", grpc::InsecureChannelCredentials()));
      grpc::ClientContext context;
      context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
      v1::GetJobRequest request;
      request.set_job_id("none");
      v1::Job job;
      EXPECT_FALSE(stub->GetJob(&context, request, &job).ok());
    }
    EXPECT_TRUE(grpc_is_initialized());
  }
  EXPECT_FALSE(grpc_is_initialized());
}

}  // namespace
}  // namespace mesh4d::wire
