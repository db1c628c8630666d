/* Loaded under the name civetweb opens, "libcrypto.so" (its SONAME), before civetweb starts, so
 * that civetweb's lookups reach OpenSSL 3's libcrypto through this library's dependency without
 * the development package's unversioned link, which a run-time image does not carry. */
#include <openssl/crypto.h>

/* The version civetweb's lookups reach, for the server's log. */
const char* mesh4d_libcrypto_version(void);
const char* mesh4d_libcrypto_version(void) {
  return OpenSSL_version(OPENSSL_VERSION);
}
