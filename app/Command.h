#pragma once
// Subcommand registry of the `rasm` executable. Each app/cmd_<name>.cpp defines one
// `static rasm::app::Registrar r{"name", "one-line help", &fn};` and stays a thin layer over a
// module or pipeline class (the logic lives in libraries so tests drive the same code).

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace rasm::app {

/// args excludes the program and subcommand names; returns the process exit code.
using CommandFn = std::function<int(const std::vector<std::string>& args)>;

struct CommandInfo {
  std::string help;
  CommandFn fn;
};

inline std::map<std::string, CommandInfo>& commands() {
  static std::map<std::string, CommandInfo> c;
  return c;
}

struct Registrar {
  Registrar(const std::string& name, const std::string& help, CommandFn fn) {
    commands()[name] = CommandInfo{help, std::move(fn)};
  }
};

}  // namespace rasm::app
