#include "rasm/pipeline/RunConfig.h"

#include <fstream>
#include <sstream>

#include "rasm/core/Error.h"
#include "rasm_default_ini.h"  // generated: kDefaultIni

namespace rasm::pipeline {

RunConfig RunConfig::embeddedDefault() {
  return fromString(kDefaultIni, "embedded default (ini/default.ini)");
}

RunConfig RunConfig::fromFile(const std::string& path) {
  std::ifstream f(path);
  if (!f) throwInputError("config file '" + path + "'", "cannot be opened (expected an INI file)");
  std::stringstream ss;
  ss << f.rdbuf();
  return fromString(ss.str(), path);
}

RunConfig RunConfig::fromString(const std::string& ini_text, const std::string& source_name) {
  RunConfig c;
  c.m_source = source_name;
  // Reject lines that are neither sections, assignments, comments nor blank: MRPT's parser would
  // skip them silently.
  std::istringstream in(ini_text);
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos) continue;
    const char ch = line[b];
    if (ch == ';' || ch == '#' || ch == '[' || line.find('=') != std::string::npos) continue;
    throwInputError(source_name + ":" + std::to_string(lineno),
                    "cannot parse '" + line + "' (expected [section], key = value, or a comment)");
  }
  c.m_ini.setContent(ini_text);
  return c;
}

void RunConfig::applyOverride(const std::string& a) {
  const auto eq = a.find('=');
  const auto dot = a.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 || dot + 1 == eq)
    throwInputError("override '" + a + "'", "expected section.key=value");
  set(a.substr(0, dot), a.substr(dot + 1, eq - dot - 1), a.substr(eq + 1));
  m_overrides.push_back(a);
}

void RunConfig::set(const std::string& section, const std::string& key, const std::string& value) {
  m_ini.write(section, key, value);
}

void RunConfig::checkSections(const std::vector<std::string>& known) const {
  std::vector<std::string> sections;
  m_ini.getAllSections(sections);
  for (const auto& s : sections) {
    if (s.empty()) continue;
    bool ok = false;
    for (const auto& k : known) ok = ok || k == s;
    if (!ok) {
      std::string list;
      for (const auto& k : known) list += " [" + k + "]";
      throwInputError(m_source + " [" + s + "]", "unknown section; this build knows" + list);
    }
  }
}

std::string RunConfig::text() const {
  std::string s;
  m_ini.getContent(s);
  std::string header = "; effective configuration, from " + m_source + "\n";
  for (const auto& o : m_overrides) header += "; override: " + o + "\n";
  return header + s;
}

}  // namespace rasm::pipeline
