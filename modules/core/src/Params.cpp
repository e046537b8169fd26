#include "rasm/core/Params.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <exception>
#include <sstream>
#include <vector>

#include "rasm/core/Error.h"

namespace rasm {

std::set<std::string> knownKeys(const mrpt::config::CLoadableOptions& params, const std::string& section) {
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
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throwInputError(source + " [" + section + "]", std::string("bad value: ") + e.what());
  }
}

void requireInRange(double value, double lo, double hi, const std::string& section, const std::string& key) {
  if (!(value >= lo && value <= hi)) {
    std::ostringstream s;
    s << "value " << value << " out of range, expected [" << lo << ", " << hi << "]";
    throwInputError("[" + section + "] " + key, s.str());
  }
}

}  // namespace rasm
