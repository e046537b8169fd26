// rasm: rapid autonomous semantic mapping. `rasm <command> [args]`; `rasm help` lists commands.
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <sstream>
#include <string>

#include "Command.h"
#include "rasm/core/Error.h"
#include "rasm/core/Printable.h"

namespace {

/// An error message as a person reads it. MRPT's exceptions carry their source location and a
/// call-stack backtrace (a dozen lines per nested exception): unless `verbose`, only the text
/// before them and the innermost MRPT "Message:" (the cause) are kept, on one line. Control
/// characters (a file name holding a terminal escape sequence) are shown as \xNN.
std::string forPeople(const std::string& what, bool verbose) {
  std::string text = what;
  const std::string marker = "==== MRPT exception ====";
  if (!verbose && what.find(marker) != std::string::npos) {
    std::istringstream in(what);
    std::string line, head, cause, tail;
    bool in_mrpt = false;
    while (std::getline(in, line)) {
      const auto at = line.find(marker);
      if (at != std::string::npos) {
        if (!in_mrpt) head += line.substr(0, at);
        in_mrpt = true;
        continue;
      }
      if (!in_mrpt) {
        head += line + " ";
      } else if (line.rfind("Message:", 0) == 0) {
        const auto b = line.find_first_not_of(' ', 8);
        cause = b == std::string::npos ? "" : line.substr(b);
      } else if (!line.empty() && line[0] != '[' && line.rfind("Location:", 0) != 0 &&
                 line.rfind("Call stack backtrace:", 0) != 0 &&
                 line.rfind("Original exception:", 0) != 0) {
        tail += " " + line;
      }
    }
    while (!head.empty() && head.back() == ' ') head.pop_back();
    text = head + (head.empty() ? "" : " ") + cause + tail +
           " (rasm --verbose shows MRPT's backtrace)";
  }
  return rasm::escapeControlChars(text);
}

}  // namespace

int main(int argc, char** argv) {
  // libgomp reads OMP_WAIT_POLICY when it is loaded, before main. Its default (spin for a while
  // before sleeping) makes every parallel region wait for descheduled threads whenever another
  // process or thread competes for the 2 cores of a robot laptop: measured 2-2.5x slower frames
  // on TUM fr1/xyz. Unless the user chose a policy, re-execute once with the passive one.
  if (!std::getenv("OMP_WAIT_POLICY") && !std::getenv("RASM_NO_REEXEC")) {
    ::setenv("OMP_WAIT_POLICY", "passive", 1);
    ::setenv("RASM_NO_REEXEC", "1", 1);
    ::execv("/proc/self/exe", argv);  // returns only on failure: then go on with the default
  }
  using namespace rasm::app;
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    printCommandList(std::cout);
    return argc < 2 ? 1 : 0;
  }
  const std::string name = std::string(argv[1]) == "--version" ? "version" : argv[1];
  const auto it = commands().find(name);
  if (it == commands().end() && !missingSimulatorReason(name).empty()) {
    std::cerr << "rasm " << name << ": " << missingSimulatorReason(name) << "\n";
    return 2;
  }
  if (it == commands().end() || name.find(' ') != std::string::npos) {
    std::cerr << "rasm: unknown command '" << forPeople(argv[1], true) << "' (try `rasm help`)\n";
    return 2;
  }
  // --verbose (any command): error messages in full, MRPT's backtraces included. It stays among
  // the arguments of a command that declares it too (rasm run: every log message).
  std::vector<std::string> args(argv + 2, argv + argc), stripped = args, rest;
  const auto v = std::remove(stripped.begin(), stripped.end(), std::string("--verbose"));
  const bool verbose = v != stripped.end() || std::getenv("RASM_VERBOSE") != nullptr;
  stripped.erase(v, stripped.end());
  const CommandInfo* info = resolveCommand(name, stripped, rest);
  if (!declaresOption(info->decl, "verbose")) args = stripped;
  if (wantsHelp(args)) {
    std::cout << usageOf(info->decl);
    return 0;
  }
  try {
    return runCommand(name, args);
  } catch (const rasm::InputError& e) {
    std::cerr << "rasm " << info->decl.name << ": error: " << forPeople(e.what(), verbose) << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "rasm " << info->decl.name << ": failed: " << forPeople(e.what(), verbose) << "\n";
    return 4;
  }
}
