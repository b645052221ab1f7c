// SHA-256 through OpenSSL's EVP interface (a well-kept library).
#pragma once

#include <string>
#include <string_view>

namespace tessera::wire {

/// The SHA-256 of `bytes` as 64 lowercase hex characters.
std::string sha256_hex(std::string_view bytes);

/// True when `text` looks like what sha256_hex returns (64 lowercase hex characters).
bool is_sha256_hex(std::string_view text);

}  // namespace tessera::wire
