#pragma once
// The configuration of one run: an INI file (or the embedded default, ini/default.ini) plus
// `--set section.key=value` overrides. Every section belongs to one stage's params struct and is
// loaded strictly (unknown keys are errors naming file, section and key); unknown sections are
// errors too, so a typo never silently falls back to a default.

#include <mrpt/config/CConfigFileMemory.h>

#include <string>
#include <vector>

namespace rasm::pipeline {

class RunConfig {
 public:
  /// The INI compiled into the binary (ini/default.ini): the simulated office.
  static RunConfig embeddedDefault();
  /// Reads `path`; InputError if missing or unreadable.
  static RunConfig fromFile(const std::string& path);
  static RunConfig fromString(const std::string& ini_text, const std::string& source_name);

  /// "section.key=value"; InputError on malformed text.
  void applyOverride(const std::string& assignment);
  /// Sets a key programmatically (tests, CLI shortcuts).
  void set(const std::string& section, const std::string& key, const std::string& value);

  /// InputError for any section not in `known` (named with this config's source).
  void checkSections(const std::vector<std::string>& known) const;

  const mrpt::config::CConfigFileMemory& ini() const { return m_ini; }
  /// Where the config came from ("ini/office.ini", "embedded default"), for messages.
  const std::string& source() const { return m_source; }
  /// The whole effective configuration as INI text (written into the output folder).
  std::string text() const;

 private:
  mrpt::config::CConfigFileMemory m_ini;
  std::string m_source;
  std::vector<std::string> m_overrides;
};

}  // namespace rasm::pipeline
