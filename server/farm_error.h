// An error the farm reports to its caller, with the gRPC code it maps to. what() is one line a
// person can act on.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace tessera::server {

/// resource_exhausted: a quota (jobs queued per client) is used up; retry when jobs finish.
enum class ErrorCode {
  invalid_argument,
  not_found,
  failed_precondition,
  resource_exhausted,
  internal
};

class FarmError : public std::runtime_error {
 public:
  FarmError(ErrorCode code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  ErrorCode code() const { return code_; }

 private:
  ErrorCode code_;
};

inline FarmError invalid_argument(const std::string& message) {
  return FarmError(ErrorCode::invalid_argument, message);
}

inline FarmError job_not_found(int64_t job_id) {
  return FarmError(ErrorCode::not_found, "no job " + std::to_string(job_id));
}

}  // namespace tessera::server
