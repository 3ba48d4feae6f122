// SHA-256 (FIPS 180-4) of a byte string, as 64 lowercase hex digits: the
// provenance hashes of specs in calibration files and reports.
#pragma once

#include <string>

namespace tbio {

std::string sha256_hex(const std::string& data);

}  // namespace tbio
