#include "civetweb_tls.h"

#include <CivetServer.h>
#include <civetweb.h>
#include <dlfcn.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/ssl.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace mesh4d::server {
namespace {

struct TlsFiles {
  std::string cert;
  std::string key;
};

// Written once by enable_civetweb_tls before any port starts, read by civetweb's threads after.
TlsFiles g_files;
std::atomic<bool> g_enabled{false};

std::string openssl_errors() {
  std::string out;
  for (unsigned long e; (e = ERR_get_error()) != 0;) {
    char text[256];
    ERR_error_string_n(e, text, sizeof text);
    out += out.empty() ? text : std::string("; ") + text;
  }
  return out.empty() ? "no detail from OpenSSL" : out;
}

// Loads the certificate chain and key into `ctx`; "" or what failed.
std::string load_certificate(SSL_CTX* ctx, const TlsFiles& files) {
  ERR_clear_error();
  if (SSL_CTX_set_min_proto_version(ctx, TLS1_2_VERSION) != 1)
    return "cannot require TLS 1.2: " + openssl_errors();
  if (SSL_CTX_use_certificate_chain_file(ctx, files.cert.c_str()) != 1)
    return "cannot read the certificate chain " + files.cert + ": " + openssl_errors();
  // Read apart from its use, so that a key of another certificate is told from a bad file.
  BIO* in = BIO_new_file(files.key.c_str(), "r");
  EVP_PKEY* key = in ? PEM_read_bio_PrivateKey(in, nullptr, nullptr, nullptr) : nullptr;
  BIO_free(in);
  if (!key) return "cannot read the private key " + files.key + ": " + openssl_errors();
  const bool matches = SSL_CTX_use_PrivateKey(ctx, key) == 1 && SSL_CTX_check_private_key(ctx) == 1;
  EVP_PKEY_free(key);
  if (!matches)
    return "the key " + files.key + " does not match the certificate " + files.cert + ": " +
           openssl_errors();
  return "";
}

// civetweb's init_ssl: 1 when the context is ready (civetweb then loads no certificate of its
// own), -1 to refuse the port.
int init_ssl(void* ssl_ctx, void*) {
  const std::string error = load_certificate(static_cast<SSL_CTX*>(ssl_ctx), g_files);
  if (error.empty()) return 1;
  spdlog::error("TLS: {}", error);
  return -1;
}

// The directories the server's own libraries are looked for in: its own, and lib/mesh4d beside
// an installed bin/.
std::filesystem::path library_path(const std::string& name) {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("TLS: cannot find the server's own path: " + ec.message());
  const auto dir = exe.parent_path();
  for (const auto& candidate : {dir / name, dir.parent_path() / "lib" / "mesh4d" / name})
    if (std::filesystem::exists(candidate)) return candidate;
  throw std::runtime_error("TLS: " + name + " is neither in " + dir.string() + " nor in " +
                           (dir.parent_path() / "lib" / "mesh4d").string() +
                           " (it is built and installed with the server)");
}

void load_under_civetweb_name(const std::string& file, const char* civetweb_name) {
  const auto path = library_path(file);
  void* ours = dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
  if (!ours) throw std::runtime_error(std::string("TLS: cannot load ") + dlerror());
  // civetweb's dlopen by name must find this one, not the system's.
  void* found = dlopen(civetweb_name, RTLD_NOW | RTLD_NOLOAD);
  if (found != ours)
    throw std::runtime_error(std::string("TLS: ") + civetweb_name + " was loaded before " +
                             path.string() + ": civetweb would reach the wrong library");
  dlclose(found);
}

}  // namespace

void enable_civetweb_tls(const std::string& cert_file, const std::string& key_file) {
  if (g_enabled) return;
  load_under_civetweb_name("libmesh4d-civetweb-libcrypto.so", "libcrypto.so");
  load_under_civetweb_name("libmesh4d-civetweb-libssl.so", "libssl.so");
  g_files = {cert_file, key_file};
  // A bad certificate or key stops the server at start with OpenSSL's reason, not at the first
  // connection.
  SSL_CTX* probe = SSL_CTX_new(TLS_server_method());
  if (!probe) throw std::runtime_error("TLS: " + openssl_errors());
  const std::string error = load_certificate(probe, g_files);
  SSL_CTX_free(probe);
  if (!error.empty()) throw std::runtime_error("TLS: " + error);
  if (!(mg_init_library(MG_FEATURES_SSL) & MG_FEATURES_SSL))
    throw std::runtime_error("TLS: civetweb could not initialize OpenSSL");
  g_enabled = true;
}

bool civetweb_tls_enabled() {
  return g_enabled;
}

std::string civetweb_listening_port(const std::string& listen) {
  return g_enabled ? listen + "s" : listen;
}

void add_tls_setup(CivetCallbacks& callbacks) {
  callbacks.init_ssl = init_ssl;
}

}  // namespace mesh4d::server
