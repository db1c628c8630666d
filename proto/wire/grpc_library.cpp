#include "wire/grpc_library.h"

#include <grpc/grpc.h>

#include <thread>

namespace mesh4d::wire {

GrpcLibrary::GrpcLibrary() {
  grpc_init();
}

GrpcLibrary::~GrpcLibrary() {
  // Blocking: when this is the last reference, the clean-up runs here, on this thread.
  grpc_shutdown_blocking();
  // When gRPC's own threads still hold references (work a channel left behind), the last of
  // them cleans up on a thread of its own: wait for it rather than exit under it.
  const auto end = std::chrono::steady_clock::now() + settle;
  while (grpc_is_initialized() && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

}  // namespace mesh4d::wire
