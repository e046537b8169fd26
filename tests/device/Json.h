#pragma once
// A minimal JSON writer for the device check's one summary (no parser, no dependencies).

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace rasm::device {

inline std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        o += "\\\"";
        break;
      case '\\':
        o += "\\\\";
        break;
      case '\n':
        o += "\\n";
        break;
      case '\t':
        o += "\\t";
        break;
      case '\r':
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", c);
          o += b;
        } else {
          o += c;
        }
    }
  }
  return o + "\"";
}

/// Numbers with up to 6 significant digits (times, differences); non-finite ones as null.
inline std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

/// An object whose members keep their insertion order.
class JsonObject {
 public:
  JsonObject& num(const std::string& k, double v) { return raw(k, jsonNumber(v)); }
  JsonObject& integer(const std::string& k, long long v) { return raw(k, std::to_string(v)); }
  JsonObject& str(const std::string& k, const std::string& v) { return raw(k, jsonString(v)); }
  JsonObject& boolean(const std::string& k, bool v) { return raw(k, v ? "true" : "false"); }
  JsonObject& obj(const std::string& k, const JsonObject& v) { return raw(k, v.dump()); }
  JsonObject& arr(const std::string& k, const std::vector<JsonObject>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i].dump();
    return raw(k, s + "]");
  }
  JsonObject& strs(const std::string& k, const std::vector<std::string>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + jsonString(v[i]);
    return raw(k, s + "]");
  }
  JsonObject& raw(const std::string& k, const std::string& json) {
    members_.emplace_back(k, json);
    return *this;
  }
  bool empty() const { return members_.empty(); }

  /// Compact members; `indent` > 0 puts each top-level member on its own line.
  std::string dump(int indent = 0) const {
    std::string s = "{";
    for (std::size_t i = 0; i < members_.size(); ++i) {
      s += i ? "," : "";
      if (indent)
        s += "\n" + std::string(indent, ' ');
      else if (i)
        s += " ";
      s += jsonString(members_[i].first) + ": " + members_[i].second;
    }
    if (indent && !members_.empty()) s += "\n";
    return s + "}";
  }

 private:
  std::vector<std::pair<std::string, std::string>> members_;
};

}  // namespace rasm::device
