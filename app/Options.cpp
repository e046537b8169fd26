#include "Options.h"

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <algorithm>
#include <cctype>
#include <memory>
#include <sstream>

#include "rasm/core/Error.h"

namespace rasm::app {

namespace {

using Given = std::vector<std::pair<std::string, std::string>>;

/// A token that looks like an option ("-x", "--name"). TCLAP gives any token no option matches
/// to a positional argument: parseArgs reports such a positional as an unknown option.
bool optionLike(const std::string& token) {
  return token.size() > 1 && token[0] == '-';
}

/// A positional's name as TCLAP accepts it (no spaces, no leading '-').
std::string tclapName(const std::string& name) {
  std::string out;
  for (const char c : name) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

/// Records each occurrence of an option in command-line order (TCLAP keeps one list per option,
/// but `--set` and the options that stand for INI keys apply in the order given).
class Recorder : public TCLAP::Visitor {
 public:
  Recorder(Given& given, std::string name) : m_given(given), m_name(std::move(name)) {}
  void bind(TCLAP::MultiArg<std::string>* arg) { m_arg = arg; }
  void visit() override {
    m_given.emplace_back(m_name, m_arg ? m_arg->getValue().back() : std::string());
  }

 private:
  Given& m_given;
  std::string m_name;
  TCLAP::MultiArg<std::string>* m_arg = nullptr;
};

/// The positional arguments of one command line as TCLAP reads them (after every option).
class PositionalArgs {
 public:
  PositionalArgs(const CommandDecl& decl, TCLAP::CmdLine& cmd) {
    for (const PositionalDecl& p : decl.positionals) {
      m_singles.emplace_back();
      m_lists.emplace_back();
      if (p.repeatable) {
        m_lists.back() = std::make_unique<TCLAP::UnlabeledMultiArg<std::string>>(
            tclapName(p.name), p.help, false, p.name);
        cmd.add(m_lists.back().get());
      } else {
        m_singles.back() = std::make_unique<TCLAP::UnlabeledValueArg<std::string>>(
            tclapName(p.name), p.help, p.required, std::string(), p.name);
        cmd.add(m_singles.back().get());
      }
    }
  }
  /// The values of the k-th positional argument (none when it was not given).
  std::vector<std::string> values(std::size_t k) const {
    if (!m_singles[k]) return m_lists[k]->getValue();
    if (!m_singles[k]->isSet()) return {};
    return {m_singles[k]->getValue()};
  }

 private:
  std::vector<std::unique_ptr<TCLAP::UnlabeledValueArg<std::string>>> m_singles;
  std::vector<std::unique_ptr<TCLAP::UnlabeledMultiArg<std::string>>> m_lists;
};

/// TCLAP's failure report, kept for parseArgs to turn into an InputError (TCLAP prints nothing
/// and exits nothing: rasm owns the output and the exit code).
class KeepFailure : public TCLAP::CmdLineOutput {
 public:
  void usage(TCLAP::CmdLineInterface&) override {}
  void version(TCLAP::CmdLineInterface&) override {}
  void failure(TCLAP::CmdLineInterface&, TCLAP::ArgException& e) override {
    failed = true;
    error = e.error();
    const std::string what = e.what();
    id = what.substr(0, what.find(" -- "));
  }
  bool failed = false;
  std::string error, id;
};

/// The option TCLAP's id "-q (--quiet)" or "(--max-frames)" names.
const OptionDecl* optionNamed(const CommandDecl& decl, const std::string& id) {
  for (const OptionDecl& o : decl.options)
    if (id.find("(--" + o.name + ")") != std::string::npos) return &o;
  return nullptr;
}

/// TCLAP's failure as an InputError naming the argument and what was expected.
[[noreturn]] void throwParseFailure(const CommandDecl& decl, const KeepFailure& f,
                                    const PositionalArgs& positionals) {
  const std::string cmd = "rasm " + decl.name;
  if (f.error.rfind("Couldn't find match", 0) == 0) {
    if (optionLike(f.id))
      throwInputError("option '" + f.id + "'", "unknown (" + cmd + " --help lists its options)");
    std::string takes;
    for (const PositionalDecl& p : decl.positionals)
      takes += (takes.empty() ? "" : " ") + (p.required ? "<" + p.name + ">" : "[" + p.name + "]") +
               (p.repeatable ? "..." : "");
    throwInputError("argument '" + f.id + "'",
                    "unexpected: " + cmd + " takes " + (takes.empty() ? "no argument" : takes));
  }
  if (f.error.rfind("Missing a value", 0) == 0) {
    if (const OptionDecl* o = optionNamed(decl, f.id))
      throwInputError("option --" + o->name, "expects a value: " + o->value + " (" + o->help + ")");
  }
  if (f.error.rfind("One or more required", 0) == 0) {
    for (std::size_t k = 0; k < decl.positionals.size(); ++k)
      if (decl.positionals[k].required && positionals.values(k).empty())
        throwInputError("<" + decl.positionals[k].name + ">",
                        "missing; expected " + decl.positionals[k].help + " (" + cmd + " --help)");
  }
  throwInputError(cmd + " " + f.id, f.error);
}

}  // namespace

bool ParsedArgs::has(const std::string& option) const {
  return std::any_of(m_given.begin(), m_given.end(),
                     [&](const auto& g) { return g.first == option; });
}

std::string ParsedArgs::value(const std::string& option, const std::string& fallback) const {
  for (auto it = m_given.rbegin(); it != m_given.rend(); ++it)
    if (it->first == option) return it->second;
  return fallback;
}

std::vector<std::string> ParsedArgs::values(const std::string& option) const {
  std::vector<std::string> out;
  for (const auto& [name, v] : m_given)
    if (name == option) out.push_back(v);
  return out;
}

std::string ParsedArgs::positional(const std::string& name) const {
  for (const auto& [n, v] : m_positional)
    if (n == name) return v;
  return "";
}

std::vector<std::string> ParsedArgs::positionals(const std::string& name) const {
  std::vector<std::string> out;
  for (const auto& [n, v] : m_positional)
    if (n == name) out.push_back(v);
  return out;
}

ParsedArgs parseArgs(const CommandDecl& decl, const std::vector<std::string>& args) {
  ParsedArgs parsed;
  TCLAP::CmdLine cmd(decl.summary, ' ', "", /*helpAndVersion=*/false);
  KeepFailure output;
  cmd.setOutput(&output);
  // TCLAP keeps "an optional positional was declared" process-wide; each command line is new.
  TCLAP::OptionalUnlabeledTracker<int>::alreadyOptional() = false;
  std::vector<std::unique_ptr<Recorder>> recorders;
  std::vector<std::unique_ptr<TCLAP::Arg>> options;
  for (const OptionDecl& o : decl.options) {
    recorders.push_back(std::make_unique<Recorder>(parsed.m_given, o.name));
    if (o.value.empty()) {
      options.push_back(std::make_unique<TCLAP::MultiSwitchArg<>>(o.short_name, o.name, o.help, 0,
                                                                  recorders.back().get()));
    } else {  // MultiArg also for single values: given twice, the last one wins (as before)
      auto arg = std::make_unique<TCLAP::MultiArg<std::string>>(o.short_name, o.name, o.help, false,
                                                                o.value, recorders.back().get());
      recorders.back()->bind(arg.get());
      options.push_back(std::move(arg));
    }
    cmd.add(options.back().get());
  }
  const PositionalArgs positionals(decl, cmd);
  std::vector<const char*> argv{"rasm"};  // TCLAP reads argv[0] as the program name
  for (const std::string& a : args) argv.push_back(a.c_str());
  const bool ok = cmd.parse(int(argv.size()), argv.data()) && !output.failed;
  for (std::size_t k = 0; k < decl.positionals.size(); ++k)
    for (const std::string& v : positionals.values(k)) {
      if (optionLike(v))
        throwInputError("option '" + v + "'",
                        "unknown (rasm " + decl.name + " --help lists its options)");
      parsed.m_positional.emplace_back(decl.positionals[k].name, v);
    }
  if (!ok) {
    for (const std::string& a : args)  // TCLAP marks the switches it took from "-qx" with '*'
      if (a.size() == output.id.size() && output.id.find('*') != std::string::npos &&
          std::equal(a.begin(), a.end(), output.id.begin(),
                     [](char x, char y) { return x == y || y == '*'; }))
        output.id = a;
    throwParseFailure(decl, output, positionals);
  }
  for (const OptionDecl& o : decl.options)
    if (o.required && !parsed.has(o.name))
      throwInputError("--" + o.name + " " + o.value, "required: " + o.help);
  for (std::size_t k = 0; k < decl.positionals.size(); ++k)
    if (decl.positionals[k].repeatable && decl.positionals[k].required &&
        positionals.values(k).empty())
      throwInputError("<" + decl.positionals[k].name + ">",
                      "missing; expected at least one: " + decl.positionals[k].help);
  return parsed;
}

bool declaresOption(const CommandDecl& decl, const std::string& name) {
  return std::any_of(decl.options.begin(), decl.options.end(),
                     [&](const OptionDecl& o) { return o.name == name; });
}

std::string optionLabel(const OptionDecl& o) {
  return (o.short_name.empty() ? "" : "-" + o.short_name + ", ") + "--" + o.name +
         (o.value.empty() ? "" : " " + o.value);
}

namespace {

/// The synopsis items of a declaration: positionals, then options.
std::vector<std::string> synopsisItems(const CommandDecl& decl) {
  std::vector<std::string> items;
  for (const PositionalDecl& p : decl.positionals) {
    const std::string more = p.repeatable ? "..." : "";
    items.push_back(p.required ? "<" + p.name + ">" + more : "[" + p.name + more + "]");
  }
  for (const OptionDecl& o : decl.options) {
    const std::string flag = (o.short_name.empty() ? "" : "-" + o.short_name + "|") + "--" + o.name;
    const std::string item = flag + (o.value.empty() ? "" : " " + o.value);
    items.push_back(o.required ? item : "[" + item + "]" + (o.repeatable ? "..." : ""));
  }
  return items;
}

/// `words` joined by spaces and wrapped at 100 columns: the first line goes on after `start`
/// characters, the next ones start with `indent` spaces.
std::string wrap(const std::vector<std::string>& words, std::size_t start, std::size_t indent) {
  std::string out;
  std::size_t col = start;
  bool line_empty = true;
  for (const std::string& w : words) {
    if (!line_empty && col + 1 + w.size() > 100) {
      out += "\n" + std::string(indent, ' ');
      col = indent;
      line_empty = true;
    }
    if (!line_empty) {
      out += ' ';
      ++col;
    }
    out += w;
    col += w.size();
    line_empty = false;
  }
  return out;
}

std::vector<std::string> splitWords(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

/// Two columns: `left` padded, `help` wrapped beside it.
void addRow(std::ostringstream& out, const std::string& left, const std::string& help) {
  constexpr std::size_t kColumn = 30;
  out << "  " << left;
  if (left.size() + 4 > kColumn)
    out << "\n" << std::string(kColumn, ' ');
  else
    out << std::string(kColumn - 2 - left.size(), ' ');
  out << wrap(splitWords(help), kColumn, kColumn) << "\n";
}

}  // namespace

std::string synopsis(const CommandDecl& decl) {
  const std::string head = "usage: rasm " + decl.name;
  return head + " " + wrap(synopsisItems(decl), head.size() + 1, head.size() + 1);
}

std::string usageText(const CommandDecl& decl, const std::vector<const CommandDecl*>& subcommands) {
  std::ostringstream out;
  if (!subcommands.empty()) {
    for (std::size_t k = 0; k < subcommands.size(); ++k) {
      const std::string s = synopsis(*subcommands[k]);
      out << (k == 0 ? s : "       " + s.substr(7)) << "\n";  // "usage:" once, then aligned
    }
    out << decl.summary << "\n\nsubcommands (rasm " << decl.name
        << " <subcommand> --help: its arguments and options):\n";
    for (const CommandDecl* sub : subcommands)
      addRow(out, sub->name.substr(decl.name.size() + 1), sub->summary);
  } else {
    out << synopsis(decl) << "\n" << decl.summary << "\n";
    if (!decl.positionals.empty()) {
      out << "\narguments:\n";
      for (const PositionalDecl& p : decl.positionals)
        addRow(out, p.required ? "<" + p.name + ">" : "[" + p.name + "]", p.help);
    }
    out << "\noptions:\n";
    for (const OptionDecl& o : decl.options)
      addRow(out, optionLabel(o),
             o.help + (o.required ? " (required)" : "") + (o.repeatable ? " (repeatable)" : ""));
    addRow(out, "-h, --help", "this usage");
  }
  if (!decl.notes.empty()) out << "\n" << decl.notes;
  return out.str();
}

}  // namespace rasm::app
