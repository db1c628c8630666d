// The e2e tests keep their temporary folders (servers' job stores and logs, meshes) when a test
// failed, to be looked at; otherwise make_temp_dir() removes them when the program ends.
#include <gtest/gtest.h>

#include "process.h"

namespace {

const bool kRegistered = [] {
  mesh4d::testing::keep_temp_dirs_if([] { return ::testing::UnitTest::GetInstance()->Failed(); });
  return true;
}();

}  // namespace
