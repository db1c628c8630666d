// TLS on the server's civetweb ports (the REST API with the dashboard, and the metrics) from the
// same PEM files as the gRPC port. civetweb's OpenSSL setup is the process's, so this is too: it
// is enabled once, before the first civetweb port starts.
#pragma once

#include <string>

struct CivetCallbacks;

namespace mesh4d::server {

/// Loads OpenSSL for civetweb (civetweb_openssl/CMakeLists.txt says why through two small
/// libraries beside the server) and checks that the key matches the certificate chain. Throws
/// std::runtime_error saying what is missing or wrong.
void enable_civetweb_tls(const std::string& cert_file, const std::string& key_file);

/// Whether enable_civetweb_tls succeeded in this process.
bool civetweb_tls_enabled();

/// civetweb's listening_ports value for `listen` (host:port): TLS only when it is enabled.
std::string civetweb_listening_port(const std::string& listen);

/// Sets `callbacks`' init_ssl, which gives each TLS port the certificate chain and key.
void add_tls_setup(CivetCallbacks& callbacks);

}  // namespace mesh4d::server
