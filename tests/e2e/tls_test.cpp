// TLS from certificate files: a server given a certificate and key speaks only TLS on every
// port (gRPC, REST with its event streams, metrics); clients given the CA connect, plain-text
// clients get no answer; half a configuration, or a key of another certificate, is refused.
#include <gtest/gtest.h>

#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "http_client.h"
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

TEST(Tls, RestEventsAndMetricsAnswerOverHttpsWithTheCaAndNotOverPlainHttp) {
  const std::string dir = make_temp_dir("mesh4d-tls-rest");
  ASSERT_TRUE(make_certificate(dir));
  const std::string ca = dir + "/cert.pem";
  RunningServer server(dir + "/data",
                       {"--tls-cert", ca, "--tls-key", dir + "/key.pem", "--token", "s3cret"});
  ASSERT_GT(server.http_port(), 0);
  const std::string base = "https://127.0.0.1:" + std::to_string(server.http_port());
  const std::vector<std::string> trusted = {"--cacert", ca, "-H", "Authorization: Bearer s3cret"};
  domain::write_nifti(domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5),
                      dir + "/sphere.nii.gz");

  auto upload = trusted;
  upload.insert(upload.end(), {"--data-binary", "@" + dir + "/sphere.nii.gz"});
  const Http submitted = curl(dir, base + "/v1/jobs?delta=3&threads=1", upload);
  ASSERT_EQ(submitted.status, 201) << submitted.headers << submitted.body;
  const std::string id = submitted.json()["job"]["id"];
  // The event stream over TLS, until it ends with the job.
  const Http events = curl(dir, base + "/v1/jobs/" + id + "/events", trusted, 120);
  EXPECT_EQ(events.status, 200) << events.headers;
  EXPECT_NE(events.body.find("JOB_STATE_SUCCEEDED"), std::string::npos) << events.body;
  const Http mesh = curl(dir, base + "/v1/jobs/" + id + "/mesh", trusted);
  EXPECT_EQ(mesh.status, 200);
  EXPECT_GT(mesh.body.size(), 1000u);

  // The dashboard's sign-in cookie is only sent back over TLS.
  const Http login =
      curl(dir, base + "/v1/login", {"--cacert", ca, "--data", R"({"token":"s3cret"})"});
  EXPECT_EQ(login.status, 204) << login.body;
  EXPECT_NE(header(login, "Set-Cookie").find("; Secure"), std::string::npos) << login.headers;

  const Http metrics =
      curl(dir, "https://127.0.0.1:" + std::to_string(server.metrics_port()) + "/metrics",
           {"--cacert", ca});
  EXPECT_EQ(metrics.status, 200);
  EXPECT_NE(metrics.body.find("mesh4d_jobs_finished_total{state=\"succeeded\"} 1"),
            std::string::npos)
      << metrics.body;

  // No answer without TLS, nor to a client that does not trust the certificate.
  EXPECT_EQ(curl(dir, "http://127.0.0.1:" + std::to_string(server.http_port()) + "/v1/jobs",
                 {"-H", "Authorization: Bearer s3cret"})
                .status,
            0);
  EXPECT_EQ(curl(dir, base + "/v1/jobs", {"-H", "Authorization: Bearer s3cret"}).status, 0);
  EXPECT_EQ(
      curl(dir, "http://127.0.0.1:" + std::to_string(server.metrics_port()) + "/metrics").status,
      0);
}

TEST(Tls, AKeyOfAnotherCertificateIsRefusedAtStart) {
  const std::string dir = make_temp_dir("mesh4d-tls-other-key");
  ASSERT_TRUE(make_certificate(dir));
  const std::string other = make_temp_dir("mesh4d-tls-other");
  ASSERT_TRUE(make_certificate(other));
  const RunResult r =
      run_command({MESH4D_SERVER_BIN, "--listen", "127.0.0.1:0", "--data-dir", dir + "/data",
                   "--metrics-listen", "", "--http-listen", "127.0.0.1:0", "--tls-cert",
                   dir + "/cert.pem", "--tls-key", other + "/key.pem"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("does not match the certificate"), std::string::npos) << r.output;
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
