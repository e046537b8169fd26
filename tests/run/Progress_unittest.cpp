// Progress (issue 19, 1): one line rewritten in place on a terminal, plain lines otherwise; the
// ETA never beyond a wall-clock limit.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "rasm/run/Progress.h"

using rasm::run::Progress;

namespace {
/// What `f` printed into a temporary file, read back.
template <typename F>
std::string printed(F&& f) {
  std::FILE* out = std::tmpfile();
  f(out);
  std::fflush(out);
  std::rewind(out);
  std::string text;
  char buf[512];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, out)) > 0;) text.append(buf, n);
  std::fclose(out);
  return text;
}
std::size_t count(const std::string& s, char c) {
  std::size_t n = 0;
  for (char x : s) n += x == c;
  return n;
}
}  // namespace

TEST(Progress, OneUpdatingLineOnATerminalPlainLinesOtherwise) {
  const auto run = [](int tty) {
    return printed([tty](std::FILE* out) {
      Progress p("frames", 10, 0.0, out, tty);  // period 0: every update prints
      for (int i = 1; i <= 3; ++i) p.update(i, "x");
      p.finish(3, "done");
    });
  };
  const std::string term = run(1), plain = run(0);
  // Terminal: four prints on one line, each from its start, erasing the rest; one newline.
  EXPECT_EQ(count(term, '\r'), 4u) << term;
  EXPECT_EQ(count(term, '\n'), 1u) << term;
  EXPECT_EQ(term.back(), '\n');
  EXPECT_NE(term.find("\033[K"), std::string::npos);
  EXPECT_NE(term.find("frames: 3/10 (30%)"), std::string::npos) << term;
  // Not a terminal: a plain line per print, no control characters.
  EXPECT_EQ(count(plain, '\n'), 4u) << plain;
  EXPECT_EQ(count(plain, '\r'), 0u);
  EXPECT_EQ(plain.find('\033'), std::string::npos);
}

TEST(Progress, EtaNeverBeyondTheTimeLimit) {
  const std::string text = printed([](std::FILE* out) {
    Progress p("frames", 1000000, 0.0, out, 0);
    p.setTimeLimit(5.0);  // 5 s from construction, however slow the frames
    p.update(1);
  });
  double eta = -1.0;
  const std::size_t at = text.find("ETA ");
  ASSERT_NE(at, std::string::npos) << text;
  eta = std::stod(text.substr(at + 4));
  EXPECT_GE(eta, 0.0);
  EXPECT_LE(eta, 5.0) << text;
}
