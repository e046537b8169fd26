#pragma once
// Documents generated from the command registry (Command.h), so they list exactly the commands
// and options the binary has: the man page rasm(1) (`rasm help man`, roff) and the bash
// completion (`rasm help completion`). The build writes both next to the binary and installs
// them (share/man/man1/rasm.1, share/bash-completion/completions/rasm).

#include <ostream>

namespace rasm::app {

/// rasm(1) in roff (man -l reads it): name, synopsis, every command and subcommand with its
/// synopsis, notes and options (from its declaration, Options.h), exit status, environment, files.
void writeManPage(std::ostream& out);

/// A bash completion script (bash builtins only: complete, compgen): commands, subcommands; each
/// one's options as its declaration lists them, with folders, files or the choices for their
/// values; --set section.key= from `rasm config` (the keys of the binary
/// that completes); files for the arguments (ini, rawlog, folders).
void writeBashCompletion(std::ostream& out);

}  // namespace rasm::app
