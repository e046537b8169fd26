#include "ShellDocs.h"

#include <iostream>
#include <regex>
#include <set>
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

/// The options a usage text names (--long, -s), sorted.
std::set<std::string> optionsOf(const std::string& usage) {
  std::set<std::string> opts;
  static const std::regex option(R"((^|[\s\[|(])(--?[A-Za-z][A-Za-z0-9-]*))");
  for (auto it = std::sregex_iterator(usage.begin(), usage.end(), option);
       it != std::sregex_iterator(); ++it)
    opts.insert((*it)[2].str());
  opts.insert("--help");
  return opts;
}

/// The subcommands a usage text names after `rasm <name>` on its usage lines ("rasm eval ate",
/// "rasm sim record", ...): words that are not placeholders or options.
std::set<std::string> subcommandsOf(const std::string& name, const std::string& usage) {
  std::set<std::string> subs;
  const std::regex line("rasm " + name + R"( ([a-z0-9][a-z0-9_-]*)(\s|$))");
  for (auto it = std::sregex_iterator(usage.begin(), usage.end(), line);
       it != std::sregex_iterator(); ++it)
    subs.insert((*it)[1].str());
  for (const auto& [key, u] : subcommandUsages()) {
    (void)u;
    if (key.rfind(name + " ", 0) == 0) subs.insert(key.substr(name.size() + 1));
  }
  return subs;
}

}  // namespace

std::string usageText(const std::string& name) {
  const std::string usage = usageOf(name, {});
  if (!usage.empty()) return usage;
  const auto it = commands().find(name);
  if (it == commands().end()) return "";
  std::ostringstream captured;  // the command prints its own usage on std::cout
  std::streambuf* old = std::cout.rdbuf(captured.rdbuf());
  try {
    it->second.fn({"--help"});
  } catch (...) {
  }
  std::cout.rdbuf(old);
  return captured.str();
}

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
  for (const auto& [name, info] : commands()) {
    out << ".TP\n.B " << name << "\n" << roffEscape(info.help) << "\n";
    const std::string usage = usageText(name);
    if (!usage.empty()) out << ".RS\n.nf\n" << roffEscape(usage) << "\n.fi\n.RE\n";
  }
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
  for (const auto& [name, info] : commands()) out << name << " ";
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
         "    --out|--bank) COMPREPLY=($(compgen -d -- \"$cur\")); return;;\n"
         "    --frames|--max-frames|--times|--seed) return;;\n"
         "  esac\n"
         "  case $cmd in\n";
  for (const auto& [name, info] : commands()) {
    const std::string usage = usageText(name);
    std::string opts;
    for (const std::string& o : optionsOf(usage)) opts += o + " ";
    std::string subs;
    for (const std::string& s : subcommandsOf(name, usage)) subs += s + " ";
    out << "    " << name << ")\n      words=\"" << opts << "\"\n";
    if (!subs.empty())
      out << "      (( COMP_CWORD == 2 )) && [[ $cur != -* ]] && words=\"" << subs << "\"\n";
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
