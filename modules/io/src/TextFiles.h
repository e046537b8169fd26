#pragma once
// Internal: line-oriented text files of the dataset formats ('#' comments, whitespace or comma
// separated fields) with "file:line" in every error.

#include <string>
#include <vector>

namespace rasm::io::detail {

struct TextLine {
  int number = 0;  ///< 1-based
  std::vector<std::string> fields;
};

/// Non-empty, non-comment lines of a file, split at spaces, tabs and commas. Throws InputError
/// "<what> <path>: file not found" when missing.
std::vector<TextLine> readFieldLines(const std::string& path, const std::string& what);

/// Parses a double; throws InputError "<path>:<line>: <field name> '<text>' is not a number".
double parseDouble(const std::string& text, const std::string& path, int line,
                   const std::string& field);

/// "<path>:<line>"
std::string where(const std::string& path, int line);

}  // namespace rasm::io::detail
