#pragma once
// Private helper: a yaml-cpp node that knows its file and key path, so every error names
// "<file>:<line>: <key path>: <problem>" (worlds and trajectory specs).

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/core/Validate.h"

namespace rasm::sim::detail {

class YNode {
 public:
  YNode(YAML::Node node, std::string source, std::string path)
      : node_(std::move(node)), source_(std::move(source)), path_(std::move(path)) {}

  /// Parses a whole document (a syntax error becomes an InputError with its line). A key given
  /// twice in one mapping is an error naming both lines (yaml-cpp would keep the first silently).
  static YNode parse(const std::string& text, const std::string& source) {
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throwInputError(source + ":" + std::to_string(e.mark.line + 1),
                      "YAML syntax error: " + e.msg);
    }
    YNode doc(root, source, "");
    doc.rejectRepeatedKeys();
    return doc;
  }

  const std::string& path() const { return path_; }
  const std::string& source() const { return source_; }
  const YAML::Node& raw() const { return node_; }
  bool isMap() const { return node_.IsMap(); }
  bool isSequence() const { return node_.IsSequence(); }
  bool isNull() const { return !node_ || node_.IsNull(); }

  [[noreturn]] void fail(const std::string& problem) const {
    const YAML::Mark m = node_.Mark();
    std::string where = source_;
    if (m.line >= 0) where += ":" + std::to_string(m.line + 1);
    throwInputError(where + ": " + (path_.empty() ? std::string("<document>") : path_), problem);
  }

  void requireMap() const {
    if (!node_.IsMap()) fail("expected a mapping (key: value pairs)");
  }
  /// Rejects keys outside `allowed` (typos must not be silently ignored).
  void allowKeys(std::initializer_list<const char*> allowed) const {
    requireMap();
    for (const auto& kv : node_) {
      const std::string k = kv.first.as<std::string>();
      bool ok = false;
      for (const char* a : allowed) ok = ok || k == a;
      if (!ok) {
        std::string list;
        for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
        YNode(kv.first, source_, join(k)).fail("unknown key; expected one of: " + list);
      }
    }
  }
  bool has(const std::string& key) const { return node_.IsMap() && node_[key]; }
  YNode operator[](const std::string& key) const {
    requireMap();
    if (!node_[key]) fail("missing key '" + key + "'");
    return YNode(node_[key], source_, join(key));
  }
  std::optional<YNode> optional(const std::string& key) const {
    requireMap();
    if (!node_[key]) return std::nullopt;
    return YNode(node_[key], source_, join(key));
  }
  std::size_t size() const { return node_.size(); }
  YNode at(std::size_t i) const {
    return YNode(node_[i], source_, path_ + "[" + std::to_string(i) + "]");
  }
  std::vector<YNode> items() const {
    if (!node_.IsSequence()) fail("expected a sequence (a YAML list)");
    std::vector<YNode> v;
    for (std::size_t i = 0; i < node_.size(); ++i) v.push_back(at(i));
    return v;
  }

  /// A finite number within +-1e6 (no quantity of a world or trajectory is larger; `.nan`,
  /// `.inf` and 1e30 are errors); the overload with bounds checks the quantity's own range.
  double asDouble() const { return asDouble(-1e6, 1e6); }
  double asDouble(double lo, double hi) const {
    if (!node_.IsScalar()) fail("expected a number");
    double v = 0;
    try {
      v = node_.as<double>();
    } catch (const YAML::Exception&) {
      fail("expected a number, got '" + node_.Scalar() + "'");
    }
    if (const std::string p = rangeProblem(v, lo, hi); !p.empty())
      fail("'" + node_.Scalar() + "': " + p);
    return v;
  }
  long long asInt(long long lo, long long hi) const {
    if (!node_.IsScalar()) fail("expected an integer");
    long long v = 0;
    try {
      v = node_.as<long long>();
    } catch (const YAML::Exception&) {
      fail("expected an integer, got '" + node_.Scalar() + "'");
    }
    if (v < lo || v > hi)
      fail("value " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]");
    return v;
  }
  bool asBool() const {
    if (!node_.IsScalar()) fail("expected true or false");
    try {
      return node_.as<bool>();
    } catch (const YAML::Exception&) {
      fail("expected true or false, got '" + node_.Scalar() + "'");
    }
  }
  std::string asString() const {
    if (!node_.IsScalar()) fail("expected a string");
    return node_.Scalar();
  }
  /// A sequence of exactly n finite numbers, each in [lo, hi].
  Eigen::VectorXd asVector(int n, double lo = -1e6, double hi = 1e6) const {
    if (!node_.IsSequence() || int(node_.size()) != n)
      fail("expected a sequence of " + std::to_string(n) + " numbers");
    Eigen::VectorXd v(n);
    for (int i = 0; i < n; ++i) v[i] = at(std::size_t(i)).asDouble(lo, hi);
    return v;
  }
  Eigen::Vector3d asVec3() const { return asVector(3); }
  /// A position [x, y, z] in metres, each within +-kMaxCoordinate_m.
  Eigen::Vector3d asPosition() const { return asVector(3, -kMaxCoordinate_m, kMaxCoordinate_m); }

 private:
  void rejectRepeatedKeys() const {
    if (node_.IsMap()) {
      std::map<std::string, int> line_of;  // key -> line of its first occurrence
      for (const auto& kv : node_) {
        const std::string k = kv.first.IsScalar() ? kv.first.Scalar() : std::string();
        const int line = kv.first.Mark().line + 1;
        const auto [it, fresh] = line_of.emplace(k, line);
        if (!fresh && !k.empty())
          YNode(kv.first, source_, join(k))
              .fail("key '" + k + "' given twice (first at line " + std::to_string(it->second) +
                    ")");
        YNode(kv.second, source_, join(k)).rejectRepeatedKeys();
      }
    } else if (node_.IsSequence()) {
      for (std::size_t i = 0; i < node_.size(); ++i) at(i).rejectRepeatedKeys();
    }
  }
  std::string join(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  YAML::Node node_;
  std::string source_;
  std::string path_;
};

}  // namespace rasm::sim::detail
