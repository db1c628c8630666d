// TLS from certificate files: a server given a certificate and key speaks only TLS; the client
// given the CA connects, a plain-text client does not; half a configuration is refused.
#include <gtest/gtest.h>

#include "process.h"
#include "server_fixture.h"

namespace mesh4d::testing {
namespace {

// A self-signed certificate for 127.0.0.1 (the address the client dials), valid for a day.
bool make_certificate(const std::string& dir) {
  const RunResult r = run_command({"/usr/bin/openssl", "req", "-x509", "-newkey", "rsa:2048",
                                   "-nodes", "-days", "1", "-subj", "/CN=localhost", "-addext",
                                   "subjectAltName=IP:127.0.0.1,DNS:localhost", "-keyout",
                                   dir + "/key.pem", "-out", dir + "/cert.pem"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.exit_code == 0;
}

TEST(Tls, ClientWithTheCaConnectsAndAPlainClientDoesNot) {
  const std::string dir = make_temp_dir("mesh4d-tls");
  ASSERT_TRUE(make_certificate(dir));
  RunningServer server(dir + "/data",
                       {"--tls-cert", dir + "/cert.pem", "--tls-key", dir + "/key.pem"});
  ASSERT_FALSE(server.address().empty());

  const RunResult secure = run_command(
      {MESH4D_CLIENT_BIN, "--server", server.address(), "--tls-ca", dir + "/cert.pem", "health"});
  EXPECT_EQ(secure.exit_code, 0) << secure.output;
  EXPECT_EQ(secure.output, "SERVING\n");

  const RunResult plain =
      run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "--timeout", "2", "health"});
  EXPECT_EQ(plain.exit_code, 3) << plain.output;
}

TEST(Tls, ACertificateWithoutItsKeyIsRefusedAtStart) {
  const std::string dir = make_temp_dir("mesh4d-tls-half");
  ASSERT_TRUE(make_certificate(dir));
  const RunResult r =
      run_command({MESH4D_SERVER_BIN, "--listen", "127.0.0.1:0", "--data-dir", dir + "/data",
                   "--metrics-listen", "", "--http-listen", "", "--tls-cert", dir + "/cert.pem"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("TLS needs both --tls-cert and --tls-key"), std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace mesh4d::testing
