// The gRPC library's lifetime in a program: one reference taken at the start of main and
// dropped at its end, on the main thread.
//
// gRPC cleans up when its last reference drops. Where that happens on one of gRPC's own threads
// (a channel's last work ending after the program let go of it), the clean-up runs on a detached
// thread, which can still run while the program exits and its static objects are destroyed,
// and abort the program after its work is done (std::logic_error from a string built from
// null). Holding a reference until the end of main makes the last drop ours, so the clean-up is
// done before main returns.
#pragma once

#include <chrono>

namespace mesh4d::wire {

class GrpcLibrary {
 public:
  GrpcLibrary();
  /// Drops the reference and waits, at most `settle`, until gRPC has cleaned up.
  ~GrpcLibrary();
  GrpcLibrary(const GrpcLibrary&) = delete;
  GrpcLibrary& operator=(const GrpcLibrary&) = delete;

  static constexpr std::chrono::milliseconds settle{2000};
};

}  // namespace mesh4d::wire
