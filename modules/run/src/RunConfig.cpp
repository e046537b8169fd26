#include "rasm/run/RunConfig.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Error.h"
#include "rasm_default_ini.h"  // generated: kDefaultIni

namespace rasm::run {

RunConfig RunConfig::embeddedDefault() {
  return fromString(kDefaultIni, "embedded default (ini/default.ini)");
}

RunConfig RunConfig::fromFile(const std::string& path) {
  if (std::filesystem::is_directory(path))
    throwInputError("config file '" + path + "'", "is a folder (expected an INI file)");
  std::ifstream f(path);
  if (!f) throwInputError("config file '" + path + "'", "cannot be opened (expected an INI file)");
  std::stringstream ss;
  ss << f.rdbuf();
  RunConfig c = fromString(ss.str(), path);
  // Paths written in an INI are relative to the INI's folder, not to where rasm was started: a
  // shipped INI names the same data from any working directory (relative to the working
  // directory, its detector would silently be off when run from elsewhere). `--set` paths stay
  // relative to the working directory. Bare names (a world, a models file) are not paths.
  struct PathKey {
    const char* section;
    const char* key;
    bool bare_name_allowed;  // a value without '/' is a name, not a path
  };
  static const PathKey kPathKeys[] = {{"source", "path", false},
                                      {"source", "groundtruth", false},
                                      {"mapper", "load_map", false},
                                      {"dnn_detector", "model", false},
                                      {"dnn_detector", "weights", false},
                                      {"dnn_detector", "names", false},
                                      {"zero_shot", "bank", false},
                                      {"zero_shot", "models", true},
                                      {"sim", "world", true},
                                      {"sim", "trajectory", true}};
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (const PathKey& k : kPathKeys) {
    std::string v = c.m_ini.read_string(k.section, k.key, "");
    const auto b = v.find_first_not_of(" \t\r\"");
    v = b == std::string::npos ? std::string() : v.substr(b, v.find_last_not_of(" \t\r\"") - b + 1);
    if (v.empty() || dir.empty() || std::filesystem::path(v).is_absolute()) continue;
    if (k.bare_name_allowed && v.find('/') == std::string::npos) continue;
    c.m_ini.write(k.section, k.key, (dir / v).lexically_normal().string());
  }
  return c;
}

RunConfig RunConfig::fromString(const std::string& ini_text, const std::string& source_name) {
  RunConfig c;
  c.m_source = source_name;
  // A UTF-8 byte order mark (some Windows editors write one) is not part of the first line.
  const bool bom = ini_text.rfind("\xEF\xBB\xBF", 0) == 0;
  const std::string text = bom ? ini_text.substr(3) : ini_text;
  // Reject lines that are neither sections, assignments, comments nor blank (MRPT's parser would
  // skip them silently), keys before any section (MRPT ignores them) and keys given twice in a
  // section (MRPT keeps the last silently). Records where each section and key is (file:line)
  // for later messages.
  std::istringstream in(text);
  std::string line, section;
  int lineno = 0;
  std::map<std::string, int> key_line;  // "section\nkey" (lower case) -> its line
  const auto lower = [](std::string t) {
    for (auto& ch : t) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return t;
  };
  const auto trim = [](const std::string& t) {
    const auto b = t.find_first_not_of(" \t\r");
    if (b == std::string::npos) return std::string();
    return t.substr(b, t.find_last_not_of(" \t\r") - b + 1);
  };
  while (std::getline(in, line)) {
    ++lineno;
    const std::string where = source_name + ":" + std::to_string(lineno);
    const auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos) continue;
    const char ch = line[b];
    if (ch == ';' || ch == '#') continue;
    if (ch == '[') {
      const auto e = line.find(']', b);
      if (e == std::string::npos)
        throwInputError(where, "unterminated section header '" + trim(line) +
                                   "' (expected [name], with its closing ']')");
      section = trim(line.substr(b + 1, e - b - 1));
      if (section.empty()) throwInputError(where, "empty section name '[]'");
      if (c.m_ini.originOfSection(section).empty()) c.m_ini.setOrigin(section, "", where);
      continue;
    }
    const auto eq = line.find('=');
    if (eq != std::string::npos) {
      const std::string key = trim(line.substr(0, eq));
      if (section.empty())
        throwInputError(where, "key '" + key +
                                   "' before any [section] (expected it under the [section] "
                                   "it belongs to)");
      const auto [it, fresh] = key_line.emplace(lower(section) + "\n" + lower(key), lineno);
      if (!fresh)
        throwInputError(where, "[" + section + "] " + key + " given twice (first at line " +
                                   std::to_string(it->second) + "); keep one");
      c.m_ini.setOrigin(section, key, where);
      continue;
    }
    throwInputError(where,
                    "cannot parse '" + line + "' (expected [section], key = value, or a comment)");
  }
  c.m_ini.setContent(text);
  return c;
}

void RunConfig::applyOverride(const std::string& a) {
  const auto eq = a.find('=');
  const auto dot = a.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 || dot + 1 == eq)
    throwInputError("override '" + a + "'", "expected section.key=value");
  const std::string section = a.substr(0, dot), key = a.substr(dot + 1, eq - dot - 1);
  set(section, key, a.substr(eq + 1));
  const std::string origin = "command line (" + a + ")";
  m_ini.setOrigin(section, key, origin);
  if (m_ini.originOfSection(section).empty()) m_ini.setOrigin(section, "", origin);
  m_overrides.push_back(a);
}

std::string RunConfig::originOf(const std::string& section, const std::string& key) const {
  const std::string o = m_ini.originOf(section, key);
  return o.empty() ? m_source : o;
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
    if (!ok && s == "explore") {
      const std::string o = m_ini.originOfSection(s);
      throwInputError((o.empty() ? m_source : o) + " [explore]",
                      "was merged into [exploration] (the same keys): write them under "
                      "[exploration], or --set exploration.KEY=value");
    }
#ifndef RASM_HAVE_SIM
    if (!ok && s == "sim_detector") {
      const std::string o = m_ini.originOfSection(s);
      throwInputError((o.empty() ? m_source : o) + " [sim_detector]",
                      "configures the simulated detector, which this rasm leaves out (built with "
                      "-DRASM_WITH_SIM=OFF): remove the section, and detect with [dnn_detector] "
                      "or [zero_shot]");
    }
#endif
    if (!ok) {
      std::string list;
      for (const auto& k : known) list += " [" + k + "]";
      const std::string o = m_ini.originOfSection(s);
      throwInputError((o.empty() ? m_source : o) + " [" + s + "]",
                      "unknown section; this build knows" + list);
    }
  }
  checkCamera();
}

void RunConfig::checkCamera() const {
  const std::string sec = "camera";
  const auto text = [&](const char* key) {
    std::string v = m_ini.read_string(sec, key, "");
    const auto b = v.find_first_not_of(" \t\r\"");
    if (b == std::string::npos) return std::string();
    return v.substr(b, v.find_last_not_of(" \t\r\"") - b + 1);
  };
  const auto fail = [&](const char* key, const std::string& expected) {
    throwInputError(std::string("camera.") + key + " = " + text(key) + " in " + originOf(sec, key),
                    expected);
  };
  const auto number = [&](const char* key, const char* what) {
    const std::string t = text(key);
    if (t.empty()) return 0.0;
    const char* b = t.c_str();
    char* e = nullptr;
    errno = 0;
    const double v = std::strtod(b, &e);
    if (e == b || *e != '\0' || errno == ERANGE || !std::isfinite(v))
      fail(key, std::string("expected a finite ") + what);
    return v;
  };
  const auto size = [&](const char* key) {
    const double v = number(key, "image size in pixels");
    if (v < 0 || v > 65535 || v != std::floor(v))
      fail(key,
           "expected an image size in pixels, a whole number in [1, 65535] (0 = the preset's)");
    return int(v);
  };
  const double fx = number("fx", "focal length > 0 (pixels)");
  const double fy = number("fy", "focal length > 0 (pixels)");
  const double cx = number("cx", "principal point (pixels)");
  const double cy = number("cy", "principal point (pixels)");
  int width = size("width"), height = size("height");
  const std::string preset = text("preset");
  if (fx == 0 && fy == 0 && cx == 0 && cy == 0) return;  // not set: the preset's or the source's
  // Above 1e5 px the field of view is below 0.4 degrees (CameraIntrinsics::problem).
  if (!(fx > 0 && fx <= 1e5))
    fail(
        "fx",
        "expected a focal length in (0, 100000] (pixels); leave fx, fy, cx, cy all 0 (or unset) to "
        "use the preset or the source's own intrinsics");
  if (fy < 0 || fy > 1e5)
    fail("fy",
         "expected a focal length in (0, 100000] (pixels), or 0 for fy = fx (a negative fy, "
         "ICL-NUIM's "
         "flipped rows, is supported through preset = icl_nuim)");
  if (!preset.empty()) {
    CameraIntrinsics p;
    try {
      p = CameraIntrinsics::preset(preset);
    } catch (const InputError& e) {
      fail("preset", e.what());
    }
    if (width == 0) width = p.width;
    if (height == 0) height = p.height;
  }
  if (width == 0 || height == 0)
    fail(width == 0 ? "width" : "height",
         "fx is given: expected width and height (pixels) or a preset giving them");
  for (const char* key : {"cx", "cy"})
    if (text(key).empty())
      throwInputError(std::string("camera.") + key + " in " + originOf(sec, "fx"),
                      "missing: fx is given, so the principal point cx, cy must be too (pixels)");
  if (!(cx >= -0.5 && cx <= width - 0.5))
    fail("cx", "expected the principal point inside the image, in [-0.5, " +
                   std::to_string(width - 0.5) + "] for a width of " + std::to_string(width));
  if (!(cy >= -0.5 && cy <= height - 0.5))
    fail("cy", "expected the principal point inside the image, in [-0.5, " +
                   std::to_string(height - 0.5) + "] for a height of " + std::to_string(height));
}

std::string RunConfig::text() const {
  std::string s;
  m_ini.getContent(s);
  std::string header = "; effective configuration, from " + m_source + "\n";
  for (const auto& o : m_overrides) header += "; override: " + o + "\n";
  return header + s;
}

}  // namespace rasm::run
