#pragma once
// Command registry of the `rasm` executable. Each app/cmd_<name>.cpp declares its command line
// once (Options.h: CommandDecl, its positionals and options) and registers it with the function
// that runs it: `const rasm::app::Registrar reg{kDecl, &fn};`. A command made of subcommands
// registers its own declaration without a function ("eval") and one per subcommand ("eval ate").
// Commands stay thin layers over module or pipeline classes (the logic lives in libraries, so
// tests drive the same code).
//
// runCommand resolves the subcommand, reads the arguments through the declaration (parseArgs) and
// calls the function. Help is uniform: `rasm <name> [sub] ... --help` (or -h anywhere) prints
// the usage generated from the declaration and exits 0 without running (main.cpp); the man page
// and the bash completion list the same options (ShellDocs.h).

#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "Options.h"

namespace rasm::app {

/// Runs a command on its parsed arguments; returns the process exit code.
using CommandFn = std::function<int(const ParsedArgs& args)>;

struct CommandInfo {
  CommandDecl decl;
  CommandFn fn;  ///< empty for a command made of subcommands
};

/// Every command and subcommand, by name ("run", "eval ate").
std::map<std::string, CommandInfo>& commands();

struct Registrar {
  Registrar(CommandDecl decl, CommandFn fn = {});
};

/// The top-level commands (no subcommands), in name order.
std::vector<const CommandInfo*> topLevelCommands();

/// The subcommands of a command ("eval": "eval ate", ...), in name order.
std::vector<const CommandDecl*> subcommandsOf(const std::string& name);

/// The command or subcommand `rasm <name> <args>` names: "eval ate" when args[0] is "ate" and
/// registered as a subcommand of "eval", else `name`; nullptr when unknown. `rest` receives the
/// arguments after the subcommand.
const CommandInfo* resolveCommand(const std::string& name, const std::vector<std::string>& args,
                                  std::vector<std::string>& rest);

/// The usage `rasm <decl.name> --help` prints (Options.h usageText, with its subcommands).
std::string usageOf(const CommandDecl& decl);

/// `rasm <name> <args>`: resolves the subcommand, parses the arguments (InputError on bad ones)
/// and runs it. A command made of subcommands without one prints its usage on stderr (exit 1);
/// an unknown subcommand is an InputError.
int runCommand(const std::string& name, const std::vector<std::string>& args);

/// Why this build has no command `name` ("sim", "eval segmentation"), when it is one that needs
/// the simulator and the build has none (-DRASM_WITH_SIM=OFF); empty otherwise.
std::string missingSimulatorReason(const std::string& name);

/// Whether the arguments ask for help (--help or -h anywhere).
bool wantsHelp(const std::vector<std::string>& args);

/// `rasm help`: the command list.
void printCommandList(std::ostream& out);

}  // namespace rasm::app
