#pragma once
// Strict INI loading for every stage's params struct (DESIGN.md "Configuration").
// A params struct derives from mrpt::config::CLoadableOptions, has in-class defaults (the paper's
// values) and implements loadFromConfigFile / saveToConfigFile for its section. The set of keys
// saveToConfigFile writes IS the set of known keys: loadParamsStrict rejects any other key in the
// section with an InputError naming the file, section and key.

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace rasm {

/// An INI held in memory that remembers where each key came from: "x.ini:12" for a key read from
/// a file, "command line (mapper.max_depth_m=3)" for a `--set` override. loadParamsStrict blames
/// a bad or unknown key on its origin instead of on the configuration as a whole.
class ConfigWithOrigins : public mrpt::config::CConfigFileMemory {
 public:
  using mrpt::config::CConfigFileMemory::CConfigFileMemory;
  void setOrigin(const std::string& section, const std::string& key, const std::string& origin);
  /// Where `section.key` came from; empty when unknown (a default).
  std::string originOf(const std::string& section, const std::string& key) const;
  /// Where `[section]` was first named (its header line or the first override into it).
  std::string originOfSection(const std::string& section) const;

 private:
  std::map<std::string, std::string> m_origins;  ///< "section\nkey" (lower case) -> origin
};

/// Keys params.saveToConfigFile(section) writes.
std::set<std::string> knownKeys(const mrpt::config::CLoadableOptions& params,
                                const std::string& section);

/// Loads `params` from `section` of `cfg`; unknown keys and unparsable values throw InputError
/// "<source> [section] key: ...", where <source> is the key's origin when `cfg` is a
/// ConfigWithOrigins ("x.ini:12", "command line (s.k=v)"). Missing keys keep their defaults.
/// Values are checked as text before the struct reads them: a number key takes a finite number
/// ("nan", "inf", "three" are errors), an integer key an integer literal that fits.
void loadParamsStrict(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                      mrpt::config::CLoadableOptions& params, const std::string& source);

/// The items of an INI list value "a, b,c": split at commas, blanks and tabs trimmed, empty
/// items skipped.
std::vector<std::string> splitList(const std::string& text);

/// Helpers for range checks inside loadFromConfigFile implementations.
void requireInRange(double value, double lo, double hi, const std::string& section,
                    const std::string& key);
/// InputError naming "[section] key" and the allowed values unless `value` is one of them.
void requireOneOf(const std::string& value, const std::vector<std::string>& allowed,
                  const std::string& section, const std::string& key);

}  // namespace rasm
