#pragma once
// SHA-256 (FIPS 180-4, computed by OpenSSL) of a byte string: the checksums of an output set's
// manifest and of start files.
#include <string>
#include <string_view>

namespace woven::io {

/// SHA-256 of `data` as 64 lowercase hex digits.
std::string sha256_hex(std::string_view data);

}  // namespace woven::io
