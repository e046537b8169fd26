#pragma once
// Private helper: a yaml-cpp node that knows its file and key path, so every error names
// "<file>:<line>: <key path>: <problem>" (worlds and trajectory specs).

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "rasm/core/Error.h"

namespace rasm::sim::detail {

class YNode {
 public:
  YNode(YAML::Node node, std::string source, std::string path)
      : node_(std::move(node)), source_(std::move(source)), path_(std::move(path)) {}

  /// Parses a whole document (a syntax error becomes an InputError with its line).
  static YNode parse(const std::string& text, const std::string& source) {
    try {
      return YNode(YAML::Load(text), source, "");
    } catch (const YAML::Exception& e) {
      throwInputError(source + ":" + std::to_string(e.mark.line + 1),
                      "YAML syntax error: " + e.msg);
    }
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

  double asDouble() const {
    if (!node_.IsScalar()) fail("expected a number");
    try {
      return node_.as<double>();
    } catch (const YAML::Exception&) {
      fail("expected a number, got '" + node_.Scalar() + "'");
    }
  }
  double asDouble(double lo, double hi) const {
    const double v = asDouble();
    if (!(v >= lo && v <= hi))
      fail("value " + node_.Scalar() + " out of range [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]");
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
  /// A sequence of exactly n numbers.
  Eigen::VectorXd asVector(int n) const {
    if (!node_.IsSequence() || int(node_.size()) != n)
      fail("expected a sequence of " + std::to_string(n) + " numbers");
    Eigen::VectorXd v(n);
    for (int i = 0; i < n; ++i) v[i] = at(std::size_t(i)).asDouble();
    return v;
  }
  Eigen::Vector3d asVec3() const { return asVector(3); }

 private:
  std::string join(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  YAML::Node node_;
  std::string source_;
  std::string path_;
};

}  // namespace rasm::sim::detail
