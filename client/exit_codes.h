// Exit codes of mesh4d-client, one per kind of failure (README.md documents them).
#pragma once

namespace mesh4d::client {

enum ExitCode : int {
  kExitOk = 0,
  kExitUsage = 2,        // bad command line (CLI11 reports the details)
  kExitUnavailable = 3,  // no server at the address, or it did not answer in time
  kExitServerError =
      4,               // the server refused the call (unknown id, bad input, ...) or is not serving
  kExitJobFailed = 5,  // the job ended FAILED or CANCELLED
  kExitLocal = 6,      // a local file could not be read or written
};

}  // namespace mesh4d::client
