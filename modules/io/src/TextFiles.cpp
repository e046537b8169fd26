#include "TextFiles.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "rasm/core/Error.h"

namespace rasm::io::detail {

std::string where(const std::string& path, int line) {
  return path + ":" + std::to_string(line);
}

std::vector<TextLine> readFieldLines(const std::string& path, const std::string& what) {
  if (std::filesystem::is_directory(path))
    throwInputError(what + " " + path, "is a folder, expected a text file");
  std::ifstream in(path);
  if (!in) throwInputError(what + " " + path, "file not found or not readable");
  std::vector<TextLine> out;
  std::string s;
  int n = 0;
  while (std::getline(in, s)) {
    ++n;
    TextLine tl;
    tl.number = n;
    std::string cur;
    for (char c : s) {
      if (c == '#') break;
      if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
        if (!cur.empty()) tl.fields.push_back(std::move(cur)), cur.clear();
      } else {
        cur.push_back(c);
      }
    }
    if (!cur.empty()) tl.fields.push_back(std::move(cur));
    if (!tl.fields.empty()) out.push_back(std::move(tl));
  }
  return out;
}

double parseDouble(const std::string& text, const std::string& path, int line,
                   const std::string& field) {
  const char* b = text.c_str();
  char* e = nullptr;
  errno = 0;
  const double v = std::strtod(b, &e);
  if (e == b || *e != '\0' || errno == ERANGE || !std::isfinite(v))
    throwInputError(where(path, line), field + " '" + text + "' is not a finite number");
  return v;
}

}  // namespace rasm::io::detail

#include "MrptErrors.h"

namespace rasm::io::detail {

std::string shortMrptMessage(const std::string& what) {
  std::string out, line;
  std::size_t pos = 0;
  while (pos <= what.size()) {
    const std::size_t e = what.find('\n', pos);
    line = what.substr(pos, e == std::string::npos ? std::string::npos : e - pos);
    const std::size_t m = line.find("Message:");
    if (m != std::string::npos) {
      std::string msg = line.substr(m + 8);
      msg.erase(0, msg.find_first_not_of(' '));
      if (!out.empty()) out += " <- ";
      out += msg;
    }
    if (e == std::string::npos) break;
    pos = e + 1;
  }
  if (out.empty()) out = what.substr(0, what.find('\n'));
  return printable(out);
}

std::string printable(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if (u >= 0x20 && u < 0x7f) {
      out.push_back(ch);
    } else {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out.push_back(hex[u >> 4]);
      out.push_back(hex[u & 15]);
    }
  }
  return out;
}

}  // namespace rasm::io::detail
