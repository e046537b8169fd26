#include "Command.h"

#include <iostream>

#include "rasm/core/Error.h"

namespace rasm::app {

std::map<std::string, CommandInfo>& commands() {
  static std::map<std::string, CommandInfo> c;
  return c;
}

Registrar::Registrar(CommandDecl decl, CommandFn fn) {
  const std::string name = decl.name;
  commands()[name] = CommandInfo{std::move(decl), std::move(fn)};
}

std::vector<const CommandInfo*> topLevelCommands() {
  std::vector<const CommandInfo*> out;
  for (const auto& [name, info] : commands())
    if (name.find(' ') == std::string::npos) out.push_back(&info);
  return out;
}

std::vector<const CommandDecl*> subcommandsOf(const std::string& name) {
  std::vector<const CommandDecl*> out;
  for (const auto& [key, info] : commands())
    if (key.size() > name.size() + 1 && key.compare(0, name.size() + 1, name + " ") == 0)
      out.push_back(&info.decl);
  return out;
}

const CommandInfo* resolveCommand(const std::string& name, const std::vector<std::string>& args,
                                  std::vector<std::string>& rest) {
  if (!args.empty()) {
    const auto sub = commands().find(name + " " + args[0]);
    if (sub != commands().end()) {
      rest.assign(args.begin() + 1, args.end());
      return &sub->second;
    }
  }
  const auto it = commands().find(name);
  rest = args;
  return it == commands().end() ? nullptr : &it->second;
}

std::string usageOf(const CommandDecl& decl) {
  return usageText(decl, subcommandsOf(decl.name));
}

std::string missingSimulatorReason(const std::string& name) {
#ifdef RASM_HAVE_MODULE_SIM
  (void)name;
  return {};
#else
  if (name != "sim" && name != "eval segmentation" && name != "eval classification") return {};
  return "needs the simulator, and this rasm was built without it (-DRASM_WITH_SIM=OFF)";
#endif
}

int runCommand(const std::string& name, const std::vector<std::string>& args) {
  std::vector<std::string> rest;
  const CommandInfo* info = resolveCommand(name, args, rest);
  if (!info) throwInputError("rasm " + name, "unknown command (rasm help lists them)");
  if (info->fn) return info->fn(parseArgs(info->decl, rest));
  if (rest.empty()) {  // a command made of subcommands, called without one
    std::cerr << usageOf(info->decl);
    return 1;
  }
  if (rest[0] == "help") {
    std::cout << usageOf(info->decl);
    return 0;
  }
  const std::string missing = missingSimulatorReason(name + " " + rest[0]);
  if (!missing.empty()) throwInputError("rasm " + name + " " + rest[0], missing);
  std::string known;
  for (const CommandDecl* sub : subcommandsOf(name))
    known += (known.empty() ? "" : ", ") + sub->name.substr(name.size() + 1);
  throwInputError("rasm " + name + " " + rest[0],
                  "unknown subcommand (expected " + known + "; rasm " + name + " --help)");
}

bool wantsHelp(const std::vector<std::string>& args) {
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

void printCommandList(std::ostream& out) {
  out << "usage: rasm <command> [args]   (rasm <command> --help: its usage; rasm --version)\n\n"
         "commands:\n";
  for (const CommandInfo* info : topLevelCommands())
    out << "  " << info->decl.name << "\t" << info->decl.summary << "\n";
}

}  // namespace rasm::app
