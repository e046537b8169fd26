#pragma once
// The command line of one rasm command, declared once (CommandDecl: its positional arguments,
// its options with their value placeholders and one-line help, free-text notes) and read through
// MRPT's bundled TCLAP (parseArgs). Everything that shows a command line is generated from the
// same declaration: `rasm <command> --help` (usageText), the man page and the bash completion
// (ShellDocs.h), so each lists every option the command accepts.

#include <string>
#include <utility>
#include <vector>

namespace rasm::app {

/// One option: `--name VALUE` (or `-s VALUE`), or a switch when `value` is empty.
struct OptionDecl {
  std::string name{};        ///< long name without "--" ("max-frames")
  std::string value{};       ///< value placeholder ("N"); empty: a switch that takes no value
  std::string help{};        ///< one line
  std::string short_name{};  ///< one letter ("q") or empty
  bool repeatable = false;   ///< each occurrence counts (--set); otherwise the last one wins
  bool required = false;
};

/// One positional argument, in order.
struct PositionalDecl {
  std::string name{};  ///< as the usage shows it ("run folder": <run folder>)
  std::string help{};  ///< one line
  bool required = true;
  bool repeatable = false;  ///< the last positional only: it takes every remaining argument
};

/// A command or subcommand ("run", "eval ate"). A command made of subcommands ("eval") declares
/// its summary and notes only; its subcommands declare their own arguments.
struct CommandDecl {
  std::string name{};     ///< "run", "eval ate"
  std::string summary{};  ///< one line: the command list, the man page
  std::vector<PositionalDecl> positionals{};
  std::vector<OptionDecl> options{};
  std::string notes{};  ///< free text after the options in the usage (lines end with '\n')
};

/// The arguments a command was given, as its declaration names them.
class ParsedArgs {
 public:
  /// Whether the option (long name) was given at least once.
  bool has(const std::string& option) const;
  /// The option's last value, or `fallback` when it was not given.
  std::string value(const std::string& option, const std::string& fallback = "") const;
  /// Every value of the option, in order.
  std::vector<std::string> values(const std::string& option) const;
  /// Every option given, as (long name, value; "" for a switch), in command-line order.
  const std::vector<std::pair<std::string, std::string>>& given() const { return m_given; }
  /// The positional's value, "" when it was not given.
  std::string positional(const std::string& name) const;
  /// Every value of a repeatable positional.
  std::vector<std::string> positionals(const std::string& name) const;

 private:
  friend ParsedArgs parseArgs(const CommandDecl& decl, const std::vector<std::string>& args);
  std::vector<std::pair<std::string, std::string>> m_given;
  std::vector<std::pair<std::string, std::string>> m_positional;  ///< (name, value), in order
};

/// Reads `args` (without the program and command names) through TCLAP as `decl` declares them.
/// An unknown option, a missing value or argument, or an argument too many is an InputError
/// naming it and what was expected (exit 3). `--help` is not handled here (main prints usageText).
ParsedArgs parseArgs(const CommandDecl& decl, const std::vector<std::string>& args);

/// Whether `decl` declares the option (long name).
bool declaresOption(const CommandDecl& decl, const std::string& name);

/// `--name VALUE`, `-s, --name VALUE`: how the usage and the man page show an option.
std::string optionLabel(const OptionDecl& o);

/// The synopsis `rasm <name> <positionals> [options]`, wrapped at 100 columns.
std::string synopsis(const CommandDecl& decl);

/// The usage `rasm <name> --help` prints: synopsis, summary, arguments, every option with its
/// placeholder and help, the notes. `subcommands`: for a command made of subcommands, theirs
/// (their synopses replace its own).
std::string usageText(const CommandDecl& decl, const std::vector<const CommandDecl*>& subcommands);

}  // namespace rasm::app
