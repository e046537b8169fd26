#pragma once
// Text from outside (file names, labels) as it may be echoed on a terminal: control characters
// (an escape sequence in a file name would recolour or rewrite the terminal) are shown as \xNN.

#include <string>

namespace rasm {

/// `text` with every C0 control character but newline and tab, and DEL, written as \xNN; other
/// bytes (UTF-8 included) unchanged.
inline std::string escapeControlChars(const std::string& text) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if ((u < 0x20 && ch != '\n' && ch != '\t') || u == 0x7f) {
      out += "\\x";
      out.push_back(hex[u >> 4]);
      out.push_back(hex[u & 15]);
    } else {
      out.push_back(ch);
    }
  }
  return out;
}

}  // namespace rasm
