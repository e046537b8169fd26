#include "rasm/core/Params.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
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
std::string lower(std::string s) {
  for (auto& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}
bool isIntegerLiteral(const std::string& s) {
  std::size_t i = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
  if (i == s.size()) return false;
  for (; i < s.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  return true;
}

/// The kind of a key, from how MRPT writes its default: integers as "%i", reals with a point or
/// an exponent; anything else is text. Booleans are not told from text keys whose default is
/// "true" (e.g. [exploration] enabled = auto | true | false): the round trip below checks them.
enum class Kind { Text, Integer, Real };
Kind kindOfDefault(const std::string& d) {
  if (isIntegerLiteral(d)) return Kind::Integer;
  double v;
  if (parseNumber(d, v)) return Kind::Real;
  return Kind::Text;
}

/// "" when `given` is a valid value of `kind`, else what is wrong with it.
std::string valueProblem(Kind kind, const std::string& given) {
  switch (kind) {
    case Kind::Text:
      return "";
    case Kind::Integer: {
      if (!isIntegerLiteral(given)) {
        double v;
        if (parseNumber(given, v) && std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15)
          return "";  // "1e3", "4.0": MRPT reads them as integers; the round trip checks the rest
        return "'" + given + "' is not an integer";
      }
      errno = 0;
      (void)std::strtoll(given.c_str(), nullptr, 10);
      if (errno == ERANGE) return "'" + given + "' is too large for an integer";
      return "";
    }
    case Kind::Real: {
      const char* b = given.c_str();
      char* e = nullptr;
      errno = 0;
      const double v = std::strtod(b, &e);
      if (given.empty() || e == b || *e != '\0') return "'" + given + "' is not a number";
      if (!std::isfinite(v) || errno == ERANGE) return "'" + given + "' is not a finite number";
      return "";
    }
  }
  return "";
}

/// The key an InputError of a loadFromConfigFile names: "[section] key: ..." -> "key".
std::string keyOfMessage(const std::string& msg, const std::string& section) {
  const std::string head = "[" + section + "] ";
  if (msg.rfind(head, 0) != 0) return "";
  const std::size_t b = head.size();
  const std::size_t e = msg.find_first_of(": =,", b);
  return msg.substr(b, e == std::string::npos ? std::string::npos : e - b);
}
}  // namespace

void ConfigWithOrigins::setOrigin(const std::string& section, const std::string& key,
                                  const std::string& origin) {
  m_origins[lower(section) + "\n" + lower(key)] = origin;
}

std::string ConfigWithOrigins::originOf(const std::string& section, const std::string& key) const {
  const auto it = m_origins.find(lower(section) + "\n" + lower(key));
  return it == m_origins.end() ? std::string() : it->second;
}

std::string ConfigWithOrigins::originOfSection(const std::string& section) const {
  return originOf(section, "");
}

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
  const auto* traced = dynamic_cast<const ConfigWithOrigins*>(&cfg);
  const auto blame = [&](const std::string& key) {
    const std::string o = traced && !key.empty() ? traced->originOf(section, key) : "";
    return o.empty() ? source : o;
  };
  const auto known = knownKeys(params, section);
  std::vector<std::string> keys;
  cfg.getAllKeys(section, keys);
  for (const auto& k : keys)
    if (!known.count(k)) {
      std::ostringstream s;
      s << "unknown key; known keys of [" << section << "] are:";
      for (const auto& kk : known) s << " " << kk;
      throwInputError(blame(k) + " [" + section + "] " + k, s.str());
    }
  // Values as text first: MRPT reads "three" as 0 and "99999999999999999999" as -1, which the
  // range checks inside loadFromConfigFile would then report as numbers never written.
  mrpt::config::CConfigFileMemory defaults;
  params.saveToConfigFile(defaults, section);
  for (const auto& k : keys) {
    const std::string given = trim(cfg.read_string(section, k, ""));
    const std::string problem =
        valueProblem(kindOfDefault(trim(defaults.read_string(section, k, ""))), given);
    if (!problem.empty()) throwInputError(blame(k) + " [" + section + "] " + k, problem);
  }
  try {
    params.loadFromConfigFile(cfg, section);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    // An integer beyond 32 bits wraps on reading: say so rather than report the wrapped value.
    mrpt::config::CConfigFileMemory echo;
    params.saveToConfigFile(echo, section);
    for (const auto& k : keys) {
      const std::string given = trim(cfg.read_string(section, k, ""));
      if (kindOfDefault(trim(defaults.read_string(section, k, ""))) != Kind::Integer ||
          !isIntegerLiteral(given))
        continue;
      const long long v = std::strtoll(given.c_str(), nullptr, 10);
      if ((v > INT_MAX || v < INT_MIN) && !sameValue(given, trim(echo.read_string(section, k, ""))))
        throwInputError(blame(k) + " [" + section + "] " + k,
                        "'" + given + "' is too large (expected an integer within +-2147483647)");
    }
    throwInputError(blame(keyOfMessage(msg, section)), msg);
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
    if (sameValue(given, read)) continue;
    if (kindOfDefault(trim(defaults.read_string(section, k, ""))) == Kind::Integer &&
        isIntegerLiteral(given))
      throwInputError(blame(k) + " [" + section + "] " + k,
                      "'" + given + "' is too large (expected an integer within +-2147483647)");
    throwInputError(blame(k) + " [" + section + "] " + k,
                    "bad value '" + given + "' (understood as '" + read + "'; expected a " +
                        kindOf(read) + ")");
  }
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

void requireOneOf(const std::string& value, const std::vector<std::string>& allowed,
                  const std::string& section, const std::string& key) {
  if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return;
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  throwInputError("[" + section + "] " + key,
                  "unknown value '" + value + "', expected one of " + list);
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
