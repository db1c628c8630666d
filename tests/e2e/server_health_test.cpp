// The real mesh4d-server on a loopback port, checked by the real mesh4d-client.
#include <gtest/gtest.h>

#include <csignal>
#include <string>

#include "process.h"

namespace mesh4d::testing {
namespace {

class ServerHealth : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = make_temp_dir("mesh4d-e2e");
    const std::string port_file = dir_ + "/port";
    server_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{MESH4D_SERVER_BIN, "--listen", "127.0.0.1:0", "--port-file",
                                 port_file, "--data-dir", dir_ + "/data", "--metrics-listen",
                                 "127.0.0.1:0", "--http-listen", "127.0.0.1:0"},
        dir_ + "/server.log");
    const std::string port = wait_for_file(port_file, std::chrono::seconds(20));
    ASSERT_FALSE(port.empty()) << "server did not report its port";
    address_ = "127.0.0.1:" + std::to_string(std::stoi(port));
  }

  std::string dir_;
  std::string address_;
  std::unique_ptr<ChildProcess> server_;
};

TEST_F(ServerHealth, ClientSeesServingAndServerStopsCleanlyOnSigterm) {
  const RunResult health = run_command({MESH4D_CLIENT_BIN, "--server", address_, "health"});
  EXPECT_EQ(health.exit_code, 0) << health.output;
  EXPECT_EQ(health.output, "SERVING\n");
  EXPECT_EQ(server_->stop(SIGTERM), 0) << "server did not exit 0 on SIGTERM";
}

TEST_F(ServerHealth, ClientReportsUnreachableServerWithItsOwnExitCode) {
  // Stop the server, then ask the address it had: nothing listens there any more.
  ASSERT_EQ(server_->stop(SIGTERM), 0);
  const RunResult health =
      run_command({MESH4D_CLIENT_BIN, "--server", address_, "--timeout", "2", "health"});
  EXPECT_EQ(health.exit_code, 3) << health.output;
  EXPECT_NE(health.output.find("no answer from server " + address_), std::string::npos)
      << health.output;
}

TEST(ClientCli, UnknownSubcommandIsAUsageError) {
  const RunResult r = run_command({MESH4D_CLIENT_BIN, "frobnicate"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace
}  // namespace mesh4d::testing
