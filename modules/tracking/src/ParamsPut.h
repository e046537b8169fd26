#pragma once
// Private helper of tracking's params structs (TrackingParams.cpp, RelocalisationParams.cpp).

#include <mrpt/config/CConfigFileBase.h>

#include <string>

namespace rasm::tracking::detail {

/// Writes key = value // comment. No name padding: padded names would become part of the key
/// that rasm::knownKeys reads back.
template <typename T>
void put(mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& key,
         const T& value, const std::string& comment) {
  c.write(s, key, value, -1, -1, comment);
}

}  // namespace rasm::tracking::detail
