#pragma once
// Subcommand registry of the `rasm` executable. Each app/cmd_<name>.cpp defines one
// `static rasm::app::Registrar r{"name", "one-line help", &fn, kUsage};` and stays a thin layer
// over a module or pipeline class (the logic lives in libraries so tests drive the same code).
//
// Help is uniform: `rasm <name> ... --help` (or -h, anywhere among the arguments) prints the
// command's usage and exits 0 without running it (main.cpp); a subcommand with its own usage
// registers it with UsageRegistrar{"name sub", kUsage} (`rasm eval exploration --help`). A command
// registered without a usage gets --help passed to it and must handle it itself (`rasm run`).

#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace rasm::app {

/// args excludes the program and subcommand names; returns the process exit code.
using CommandFn = std::function<int(const std::vector<std::string>& args)>;

struct CommandInfo {
  std::string help;  ///< one line for the command list
  CommandFn fn;
  std::string usage;  ///< `rasm <name> --help`; empty: the command handles --help itself
};

inline std::map<std::string, CommandInfo>& commands() {
  static std::map<std::string, CommandInfo> c;
  return c;
}

/// Usages of subcommands, keyed "command subcommand".
inline std::map<std::string, std::string>& subcommandUsages() {
  static std::map<std::string, std::string> u;
  return u;
}

struct Registrar {
  Registrar(const std::string& name, const std::string& help, CommandFn fn,
            const std::string& usage = "") {
    commands()[name] = CommandInfo{help, std::move(fn), usage};
  }
};

struct UsageRegistrar {
  UsageRegistrar(const std::string& command_and_subcommand, const std::string& usage) {
    subcommandUsages()[command_and_subcommand] = usage;
  }
};

/// Whether the arguments ask for help (--help or -h anywhere).
inline bool wantsHelp(const std::vector<std::string>& args) {
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

/// The usage `rasm <name> <args>` --help prints: the subcommand's (args[0]) when it has one, else
/// the command's; empty when neither is registered (the command handles --help itself).
inline std::string usageOf(const std::string& name, const std::vector<std::string>& args) {
  if (!args.empty()) {
    const auto sub = subcommandUsages().find(name + " " + args[0]);
    if (sub != subcommandUsages().end()) return sub->second;
  }
  const auto it = commands().find(name);
  return it == commands().end() ? std::string() : it->second.usage;
}

/// `rasm help`: the command list.
inline void printCommandList(std::ostream& out) {
  out << "usage: rasm <command> [args]   (rasm <command> --help: its usage; rasm --version)\n\n"
         "commands:\n";
  for (const auto& [name, info] : commands()) out << "  " << name << "\t" << info.help << "\n";
}

}  // namespace rasm::app
