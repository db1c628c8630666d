/* Loaded under the name civetweb opens, "libssl.so" (its SONAME), before civetweb starts:
 * civetweb's dlopen finds it already loaded, and its dlsym lookups reach OpenSSL 3's libssl through
 * this library's dependencies. The one function of OpenSSL 1.1's API that OpenSSL 3 no longer
 * exports under its old name is defined here; Debian's civetweb calls it after every TLS handshake.
 */
#include <openssl/ssl.h>

#undef SSL_get_peer_certificate /* OpenSSL 3's headers make it a macro for the new name */

X509* SSL_get_peer_certificate(const SSL* ssl);

/* Both names return a new reference to the peer's certificate: the rename only made that plain. */
X509* SSL_get_peer_certificate(const SSL* ssl) {
  return SSL_get1_peer_certificate(ssl);
}
