#include "ShellDocs.h"

#include <algorithm>
#include <iostream>
#include <sstream>

#include "Command.h"
#include "rasm/pipeline/BuildInfo.h"

namespace rasm::app {

namespace {

/// Text as roff shows it literally: backslashes doubled, a leading '.' or '\'' escaped.
std::string roffEscape(const std::string& text) {
  std::string out;
  std::istringstream in(text);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::string esc;
    for (const char c : line) {
      if (c == '\\')
        esc += "\\e";
      else if (c == '-')
        esc += "\\-";
      else
        esc += c;
    }
    if (!esc.empty() && (esc[0] == '.' || esc[0] == '\'')) esc = "\\&" + esc;
    out += (first ? "" : "\n") + esc;
    first = false;
  }
  return out;
}

/// `rasm <name>` in the man page: its summary, synopsis, notes, arguments and options; a command
/// made of subcommands is followed by each subcommand as an entry of its own.
void writeManCommand(std::ostream& out, const CommandDecl& decl) {
  out << ".TP\n.B " << roffEscape(decl.name) << "\n" << roffEscape(decl.summary) << "\n";
  const std::vector<const CommandDecl*> subs = subcommandsOf(decl.name);
  if (!subs.empty()) {
    if (!decl.notes.empty()) out << ".RS\n.nf\n" << roffEscape(decl.notes) << "\n.fi\n.RE\n";
    for (const CommandDecl* sub : subs) writeManCommand(out, *sub);
    return;
  }
  out << ".RS\n.nf\n" << roffEscape(synopsis(decl)) << "\n";
  if (!decl.notes.empty()) out << "\n" << roffEscape(decl.notes) << "\n";
  out << ".fi\n";
  if (!decl.positionals.empty()) {
    out << ".PP\nArguments:\n";
    for (const PositionalDecl& p : decl.positionals)
      out << ".TP\n.I " << roffEscape(p.name) << "\n"
          << roffEscape(p.help + (p.required ? "" : " (optional)")) << "\n";
  }
  out << ".PP\nOptions:\n";
  for (const OptionDecl& o : decl.options)
    out << ".TP\n.B " << roffEscape(optionLabel(o)) << "\n"
        << roffEscape(o.help + (o.required ? " (required)" : "") +
                      (o.repeatable ? " (repeatable)" : ""))
        << "\n";
  out << ".TP\n.B \\-h, \\-\\-help\nthis usage\n.RE\n";
}

/// How the completion completes an option's value: "dirs" (a folder), "files", the words of a
/// choice ("on off"), or "" (a number, coordinates: nothing to offer).
std::string valueCompletion(const OptionDecl& o) {
  if (o.value.find("DIR") != std::string::npos) return "dirs";
  if (o.value.find('|') != std::string::npos &&
      o.value.find_first_not_of("abcdefghijklmnopqrstuvwxyz_|") == std::string::npos) {
    std::string words = o.value;
    std::replace(words.begin(), words.end(), '|', ' ');
    return words;
  }
  if (o.value.find('.') != std::string::npos || o.value.find('|') != std::string::npos ||
      o.value == "name" || o.value == "preset")
    return "files";
  return "";
}

/// The bash lines that complete the arguments of one command or subcommand: the value of the
/// option before the cursor, else its options (`words`).
void writeCompletionCase(std::ostream& out, const CommandDecl& decl, const std::string& indent) {
  out << indent << "case $prev in\n";
  for (const OptionDecl& o : decl.options) {
    if (o.value.empty() || o.name == "set") continue;  // --set: the keys, before this case
    const std::string how = valueCompletion(o);
    out << indent << "  --" << o.name << (o.short_name.empty() ? "" : "|-" + o.short_name) << ") ";
    if (how == "dirs")
      out << "COMPREPLY=($(compgen -d -- \"$cur\")); ";
    else if (how == "files")
      out << "COMPREPLY=($(compgen -f -- \"$cur\")); ";
    else if (!how.empty())
      out << "COMPREPLY=($(compgen -W \"" << how << "\" -- \"$cur\")); ";
    out << "return;;\n";
  }
  out << indent << "esac\n" << indent << "words=\"";
  for (const OptionDecl& o : decl.options)
    out << (o.short_name.empty() ? "" : "-" + o.short_name + " ") << "--" << o.name << " ";
  out << "--help\"\n";
}

}  // namespace

void writeManPage(std::ostream& out) {
  out << ".TH RASM 1 \"" << pipeline::buildInfo().date << "\" \"rasm "
      << pipeline::buildInfo().version << "\" \"User Commands\"\n"
      << ".SH NAME\nrasm \\- rapid autonomous semantic mapping with an RGB\\-D camera and a "
         "ground robot\n"
      << ".SH SYNOPSIS\n.B rasm\n.I command\n[\\fIargs\\fR] [\\fB\\-\\-verbose\\fR]\n.br\n"
         ".B rasm run\n[\\fIfile.ini\\fR | \\fIFOLDER\\fR | \\fIFILE.rawlog\\fR] "
         "[\\fB\\-\\-set\\fR \\fIsection.key=value\\fR ...] [\\fB\\-\\-out\\fR \\fIDIR\\fR]\n"
      << ".SH DESCRIPTION\nrasm maps a room with an RGB\\-D camera: surfel SLAM, geometric "
         "segmentation, object classification fused by Bayes updates, and (on a simulated or "
         "Segway robot) exploration that picks views by information gain. Without arguments "
         "\\fBrasm run\\fR explores the embedded simulated office and writes a run folder "
         "(map, trajectory, objects, floor plan, report). \\fBrasm help outputs\\fR describes "
         "every file of a run folder. Configuration is INI (MRPT's format); \\fBrasm config\\fR "
         "prints every key with its value.\n"
      << ".SH COMMANDS\n";
  for (const CommandInfo* info : topLevelCommands()) writeManCommand(out, info->decl);
  out << ".SH OPTIONS\n.TP\n.B \\-\\-verbose\n(any command) error messages in full, MRPT's "
         "backtraces included.\n.TP\n.BR \\-\\-help \", \" \\-h\n(any command) its usage.\n"
      << ".SH EXIT STATUS\n.TP\n.B 0\nsuccess\n.TP\n.B 1\nno command given\n.TP\n.B 2\n"
         "unknown command\n.TP\n.B 3\nbad input: the message names the file, section, key or "
         "argument and what was expected\n.TP\n.B 4\nfailure while running\n"
      << ".SH ENVIRONMENT\n.TP\n.B RASM_VERBOSE\nas \\-\\-verbose.\n.TP\n.B OMP_WAIT_POLICY\n"
         "rasm sets it to passive unless given (spinning OpenMP threads slow a shared 2\\-core "
         "machine down).\n.TP\n.B DISPLAY\n\\fBrasm run \\-\\-view\\fR and \\fBrasm view\\fR "
         "open a window on it.\n"
      << ".SH FILES\n.TP\n.I share/rasm/ini/\nexample configurations (default.ini: the embedded "
         "default; live OpenNI2 and Segway RMP runs).\n.TP\n.I share/rasm/sim/\nthe simulated "
         "worlds, object models and robot paths.\n.TP\n.I share/doc/rasm/\nREADME.md and docs/.\n"
      << ".SH SEE ALSO\n.BR RawLogViewer (1),\n.BR SceneViewer3D (1)\n";
}

void writeBashCompletion(std::ostream& out) {
  out << "# bash completion for rasm (generated by `rasm help completion`; rasm "
      << pipeline::buildInfo().version << ")\n"
      << "_rasm_set_keys() {\n"
         "  # section.key= of every key `rasm config` prints (once per shell)\n"
         "  if [[ -z ${_RASM_SET_KEYS+x} ]]; then\n"
         "    _RASM_SET_KEYS=$(\"${1:-rasm}\" config 2>/dev/null | awk '/^\\[/{s=substr($0,2,"
         "length($0)-2)} /^[a-z_0-9]+ *=/{print s\".\"$1\"=\"}')\n"
         "  fi\n"
         "  printf '%s\\n' \"$_RASM_SET_KEYS\"\n"
         "}\n"
         "_rasm() {\n"
         "  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}\n"
         "  local cmd=${COMP_WORDS[1]} words\n"
         "  if (( COMP_CWORD == 1 )); then\n"
         "    words=\"";
  for (const CommandInfo* info : topLevelCommands()) out << info->decl.name << " ";
  out << "--help --version\"\n"
         "    COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
         "    return\n"
         "  fi\n"
         "  case $prev in\n"
         "    --set)\n"
         "      local IFS=$'\\n'\n"
         "      COMPREPLY=($(compgen -W \"$(_rasm_set_keys \"${COMP_WORDS[0]}\")\" -- \"$cur\"))\n"
         "      compopt -o nospace 2>/dev/null\n"
         "      return;;\n"
         "  esac\n"
         "  case $cmd in\n";
  for (const CommandInfo* info : topLevelCommands()) {
    const CommandDecl& decl = info->decl;
    out << "    " << decl.name << ")\n";
    const std::vector<const CommandDecl*> subs = subcommandsOf(decl.name);
    if (subs.empty()) {
      writeCompletionCase(out, decl, "      ");
    } else {
      std::string names;
      out << "      words=\"--help\"\n      case ${COMP_WORDS[2]} in\n";
      for (const CommandDecl* sub : subs) {
        const std::string word = sub->name.substr(decl.name.size() + 1);
        names += word + " ";
        out << "        " << word << ")\n";
        writeCompletionCase(out, *sub, "          ");
        out << "          ;;\n";
      }
      out << "      esac\n      (( COMP_CWORD == 2 )) && [[ $cur != -* ]] && words=\"" << names
          << "\"\n";
    }
    out << "      ;;\n";
  }
  out << "  esac\n"
         "  if [[ $cur == -* ]]; then\n"
         "    COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
         "  else\n"
         "    COMPREPLY=($(compgen -W \"$words\" -- \"$cur\" | grep -v '^-') $(compgen -f -- "
         "\"$cur\"))\n"
         "  fi\n"
         "}\n"
         "complete -o filenames -F _rasm rasm\n";
}

}  // namespace rasm::app
