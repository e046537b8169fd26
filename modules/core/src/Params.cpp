#include "rasm/core/Params.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <vector>

#include "rasm/core/Error.h"

namespace rasm {

namespace {
std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n\"");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n\"");
  return s.substr(b, e - b + 1);
}
bool parseNumber(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}
int parseBool(std::string s) {
  for (auto& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  if (s == "true" || s == "yes" || s == "on" || s == "1") return 1;
  if (s == "false" || s == "no" || s == "off" || s == "0") return 0;
  return -1;
}
bool sameValue(const std::string& given, const std::string& read) {
  if (given == read) return true;
  double a, b;
  if (parseNumber(given, a) && parseNumber(read, b))
    return std::fabs(a - b) <= 1e-6 * std::max(1.0, std::fabs(b));
  const int ga = parseBool(given), rb = parseBool(read);
  return ga >= 0 && ga == rb;
}
std::string kindOf(const std::string& read) {
  double v;
  if (parseBool(read) >= 0 && !parseNumber(read, v)) return "boolean (true/false)";
  if (parseNumber(read, v)) return "number";
  return "value";
}
}  // namespace

std::set<std::string> knownKeys(const mrpt::config::CLoadableOptions& params,
                                const std::string& section) {
  mrpt::config::CConfigFileMemory mem;
  params.saveToConfigFile(mem, section);
  std::vector<std::string> keys;
  mem.getAllKeys(section, keys);
  return {keys.begin(), keys.end()};
}

void loadParamsStrict(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                      mrpt::config::CLoadableOptions& params, const std::string& source) {
  const auto known = knownKeys(params, section);
  std::vector<std::string> keys;
  cfg.getAllKeys(section, keys);
  for (const auto& k : keys)
    if (!known.count(k)) {
      std::ostringstream s;
      s << "unknown key; known keys of [" << section << "] are:";
      for (const auto& kk : known) s << " " << kk;
      throwInputError(source + " [" + section + "] " + k, s.str());
    }
  try {
    params.loadFromConfigFile(cfg, section);
  } catch (const InputError& e) {
    throwInputError(source, e.what());
  } catch (const std::exception& e) {
    throwInputError(source + " [" + section + "]", std::string("bad value: ") + e.what());
  }
  // MRPT parses numbers with atoi/atof semantics ("3x" reads as 3, "abc" as 0). Re-save what was
  // read and compare it with the text given: a value that did not survive the round trip was not
  // understood.
  mrpt::config::CConfigFileMemory echo;
  params.saveToConfigFile(echo, section);
  for (const auto& k : keys) {
    const std::string given = trim(cfg.read_string(section, k, "")),
                      read = trim(echo.read_string(section, k, ""));
    if (!sameValue(given, read))
      throwInputError(source + " [" + section + "] " + k,
                      "bad value '" + given + "' (understood as '" + read + "'; expected a " +
                          kindOf(read) + ")");
  }
}

void requireInRange(double value, double lo, double hi, const std::string& section,
                    const std::string& key) {
  if (!(value >= lo && value <= hi)) {
    std::ostringstream s;
    s << "value " << value << " out of range, expected [" << lo << ", " << hi << "]";
    throwInputError("[" + section + "] " + key, s.str());
  }
}

}  // namespace rasm
