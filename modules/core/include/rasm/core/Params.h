#pragma once
// Strict INI loading for every stage's params struct (DESIGN.md "Configuration").
// A params struct derives from mrpt::config::CLoadableOptions, has in-class defaults (the paper's
// values) and implements loadFromConfigFile / saveToConfigFile for its section. The set of keys
// saveToConfigFile writes IS the set of known keys: loadParamsStrict rejects any other key in the
// section with an InputError naming the file, section and key.

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <set>
#include <string>

namespace rasm {

/// Keys params.saveToConfigFile(section) writes.
std::set<std::string> knownKeys(const mrpt::config::CLoadableOptions& params,
                                const std::string& section);

/// Loads `params` from `section` of `cfg`; unknown keys and unparsable values throw InputError
/// "<source> [section] key: ...". Missing keys keep their defaults.
void loadParamsStrict(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                      mrpt::config::CLoadableOptions& params, const std::string& source);

/// Helpers for range checks inside loadFromConfigFile implementations.
void requireInRange(double value, double lo, double hi, const std::string& section,
                    const std::string& key);

}  // namespace rasm
