// The main of the tests that make temporary folders (tests/e2e, tests/server). It keeps the
// folders (servers' job stores and logs, meshes) when a test failed, to be looked at, and
// removes them otherwise.
//
// It ends the program without destroying its static objects. Threads that gRPC started can still
// run after main returns and read static objects that exit() is destroying: the soak test
// aborted that way after it had passed (std::logic_error once, std::bad_alloc once), although
// the tests hold gRPC until the end of main and wait for its clean-up (wire/grpc_library.h).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "process.h"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  mesh4d::testing::keep_temp_dirs_if([] { return ::testing::UnitTest::GetInstance()->Failed(); });
  const int status = RUN_ALL_TESTS();
  mesh4d::testing::remove_temp_dirs();
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  std::_Exit(status);
}
