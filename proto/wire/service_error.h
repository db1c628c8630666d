// The job service's errors, independent of the transport: the gRPC service maps them to status
// codes and the REST face to HTTP statuses, from this one list; the wire codecs throw them.
#pragma once

#include <stdexcept>
#include <string>

namespace mesh4d::wire {

enum class ErrorCode {
  invalid_argument,     // bad header, size or checksum mismatch, bad parameters
  not_found,            // unknown job id
  failed_precondition,  // e.g. the result of an unfinished or failed job
  cancelled,            // the result of a job that was cancelled
  resource_exhausted,   // queue full, image or vertex budget over the limit
  internal,             // the server's own fault (disk full, ...)
  data_loss,            // a stored result that no longer matches the checksum taken at writing
  already_exists,       // a request_id reused for a different image or parameters
};

class ServiceError : public std::runtime_error {
 public:
  ServiceError(ErrorCode code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  ErrorCode code() const { return code_; }

 private:
  ErrorCode code_;
};

}  // namespace mesh4d::wire
