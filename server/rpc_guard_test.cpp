// The common frame of the RPC handlers (server/rpc_guard.h): what a refused call's status says.
#include "rpc_guard.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace tessera::server {
namespace {

TEST(RpcGuardStatus, AMessageOfAnyLengthFitsGrpcsTrailer) {
  const grpc::Status status = bounded(status_of("SubmitJob", []() -> grpc::Status {
    throw FarmError(ErrorCode::invalid_argument, "bad key " + std::string(50'000'000, 'k'));
  }));
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_LE(status.error_message().size(), kStatusMessageBytes + 3);  // + the "…"
  EXPECT_EQ(status.error_message().rfind("bad key kkk", 0), 0u);
}

TEST(RpcGuardStatus, ANulDoesNotCutTheMessageShort) {
  const grpc::Status status = bounded(
      {grpc::StatusCode::INVALID_ARGUMENT, std::string("before\0after\nnext line", 22)});
  EXPECT_EQ(status.error_message(), "before\\x00after\\x0anext line");
}

TEST(RpcGuardStatus, AnUnexpectedExceptionIsInternalWithItsMessage) {
  const grpc::Status status =
      status_of("ListJobs", []() -> grpc::Status { throw std::runtime_error("disk gone"); });
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INTERNAL);
  EXPECT_EQ(status.error_message(), "disk gone");
  EXPECT_TRUE(bounded(grpc::Status::OK).ok());
}

}  // namespace
}  // namespace tessera::server
