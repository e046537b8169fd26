#pragma once
// The configuration of one run: an INI file (or the embedded default, ini/default.ini) plus
// `--set section.key=value` overrides. Every section belongs to one stage's params struct and is
// loaded strictly (unknown keys are errors naming file, section and key); unknown sections are
// errors too, so a typo never silently falls back to a default. Every key remembers where it came
// from ("x.ini:12", "command line (mapper.max_depth_m=3)"), and errors blame that origin.

#include <mrpt/config/CConfigFileMemory.h>

#include "rasm/core/Params.h"

#include <string>
#include <vector>

namespace rasm::run {

class RunConfig {
 public:
  /// The INI compiled into the binary (ini/default.ini): the simulated office.
  static RunConfig embeddedDefault();
  /// Reads `path`; InputError if missing or unreadable.
  static RunConfig fromFile(const std::string& path);
  static RunConfig fromString(const std::string& ini_text, const std::string& source_name);

  /// "section.key=value" (a `--set` of the command line); InputError on malformed text. Errors
  /// about the key later name "command line (section.key=value)", not the INI file.
  void applyOverride(const std::string& assignment);
  /// Sets a key programmatically (tests, CLI shortcuts).
  void set(const std::string& section, const std::string& key, const std::string& value);

  /// InputError for any section not in `known` (named with its origin: INI file:line or the
  /// command line). Also checks at this boundary what no params struct can check for itself:
  /// [camera] intrinsics (checkCamera).
  void checkSections(const std::vector<std::string>& known) const;

  /// [camera]: fx, fy, cx, cy finite numbers; either all 0 / absent (the preset's or the
  /// source's own intrinsics) or fx > 0, fy >= 0 (0 = fx), cx and cy given and inside the image
  /// (width x height, or the preset's size); width and height integers in [0, 65535].
  /// InputError "camera.fx = nan in x.ini:9: expected a finite focal length > 0 (pixels)".
  void checkCamera() const;

  const mrpt::config::CConfigFileMemory& ini() const { return m_ini; }
  /// Where the config came from ("ini/office.ini", "embedded default"), for messages.
  const std::string& source() const { return m_source; }
  /// The whole effective configuration as INI text (written into the output folder).
  std::string text() const;

 private:
  ConfigWithOrigins m_ini;
  std::string m_source;
  std::vector<std::string> m_overrides;
  /// Where section.key came from, for messages ("x.ini:12", "command line (s.k=v)").
  std::string originOf(const std::string& section, const std::string& key) const;
};

}  // namespace rasm::run
