// The command line read through the declarations (app/Options.h, app/Command.h): every command's
// and subcommand's --help lists every option and argument it declares, bad arguments are input
// errors (exit 3) naming the option, and the man page and the bash completion carry the same
// options. The registry is read in-process (test_app links the app's commands); the binary is run
// for what the user sees.
#include <gtest/gtest.h>

#include <sstream>

#include "Command.h"
#include "Options.h"
#include "RasmProcess.h"
#include "ShellDocs.h"
#include "rasm/core/Error.h"

using namespace rasm::app;
using rasm::app::testing::Result;
using rasm::app::testing::runRasm;

namespace {

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// The InputError message parseArgs throws for `args`, "" when it accepts them.
std::string parseError(const CommandDecl& decl, const std::vector<std::string>& args) {
  try {
    parseArgs(decl, args);
  } catch (const rasm::InputError& e) {
    return e.what();
  }
  return "";
}

/// `text` with its dashes as roff writes them.
std::string roffDashes(const std::string& text) {
  std::string roff;
  for (const char c : text) roff += c == '-' ? std::string("\\-") : std::string(1, c);
  return roff;
}

const CommandDecl kSample{"sample",
                          "a command for the tests",
                          {{"in", "the input"}, {"more", "optional further inputs", false, true}},
                          {{"set", "section.key=value", "one key", "", true},
                           {"out", "DIR", "the output folder"},
                           {"force", "", "a switch"},
                           {"quiet", "", "fewer messages", "q"},
                           {"seed", "N", "a required value", "", false, true}}};

}  // namespace

TEST(Options, OptionsKeepTheirOrderAndTheLastValueWins) {
  const ParsedArgs a =
      parseArgs(kSample, {"a.ini", "--set", "x.y=1", "--out", "d1", "-q", "--seed", "7", "b",
                          "--set", "x.y=2", "--out", "d2", "c", "--force"});
  EXPECT_EQ(a.positional("in"), "a.ini");
  EXPECT_EQ(a.positionals("more"), (std::vector<std::string>{"b", "c"}));
  EXPECT_EQ(a.values("set"), (std::vector<std::string>{"x.y=1", "x.y=2"}));
  EXPECT_EQ(a.value("out"), "d2");
  EXPECT_TRUE(a.has("force"));
  EXPECT_TRUE(a.has("quiet"));
  EXPECT_FALSE(parseArgs(kSample, {"a", "--seed", "1"}).has("force"));
  ASSERT_EQ(a.given().size(), 7u);
  EXPECT_EQ(a.given()[0], (std::pair<std::string, std::string>{"set", "x.y=1"}));
  EXPECT_EQ(a.given()[2], (std::pair<std::string, std::string>{"quiet", ""}));
  EXPECT_EQ(a.given()[6], (std::pair<std::string, std::string>{"force", ""}));
}

TEST(Options, BadArgumentsNameTheOptionAndWhatWasExpected) {
  EXPECT_TRUE(has(parseError(kSample, {"a", "--seed", "1", "--frobnicate"}),
                  "option '--frobnicate': unknown"));
  EXPECT_TRUE(has(parseError(kSample, {"--frobnicate", "a", "--seed", "1"}),
                  "option '--frobnicate': unknown"));
  EXPECT_TRUE(has(parseError(kSample, {"a", "--seed", "1", "-qx"}), "option '-qx': unknown"));
  EXPECT_TRUE(has(parseError(kSample, {"a", "--seed", "1", "--out"}),
                  "option --out: expects a value: DIR"));
  EXPECT_TRUE(has(parseError(kSample, {"--seed", "1"}), "<in>: missing"));
  EXPECT_TRUE(has(parseError(kSample, {"a"}), "--seed N: required"));
  const CommandDecl one{"one", "one argument", {{"in", "the input"}}, {}};
  EXPECT_TRUE(has(parseError(one, {"a", "b"}), "argument 'b': unexpected"));
}

TEST(Options, EveryDeclarationParsesAndRefusesBadOptionsByName) {
  ASSERT_GT(commands().size(), 20u);
  for (const auto& [name, info] : commands()) {
    if (!info.fn) continue;  // made of subcommands: no arguments of its own
    const CommandDecl& d = info.decl;
    EXPECT_TRUE(has(parseError(d, {"--no-such-option"}), "option '--no-such-option': unknown"))
        << name << ": " << parseError(d, {"--no-such-option"});
    for (const OptionDecl& o : d.options) {
      if (o.value.empty()) continue;
      const std::string e = parseError(d, {"--" + o.name});
      EXPECT_TRUE(has(e, "option --" + o.name + ": expects a value")) << name << ": " << e;
    }
  }
}

TEST(Options, EveryCommandsHelpListsEveryOptionAndArgument) {
  for (const auto& [name, info] : commands()) {
    const Result r = runRasm(name + " --help");
    EXPECT_EQ(r.status, 0) << "rasm " << name << " --help:\n" << r.output;
    EXPECT_EQ(r.output.rfind("usage: rasm " + name, 0), 0u) << r.output;
    EXPECT_EQ(r.output, usageOf(info.decl)) << name;
    for (const OptionDecl& o : info.decl.options)
      EXPECT_TRUE(has(r.output, "  " + optionLabel(o) + " ") ||
                  has(r.output, "  " + optionLabel(o) + "\n"))
          << name << " lacks " << optionLabel(o);
    for (const PositionalDecl& p : info.decl.positionals)
      EXPECT_TRUE(has(r.output, p.name)) << name << " lacks <" << p.name << ">";
    if (!info.decl.notes.empty()) {
      EXPECT_TRUE(has(r.output, info.decl.notes)) << name;
    }
    for (const CommandDecl* sub : subcommandsOf(name))  // a parent shows its subcommands' synopses
      EXPECT_TRUE(has(r.output, sub->name)) << name << " lacks " << sub->name;
  }
}

TEST(Options, BadOptionsExitWith3AndNameTheOption) {
  for (const std::string args :
       {"run --frobnicate", "eval ate --frobnicate a b", "sim record --frobnicate", "view -x"}) {
    const Result r = runRasm(args);
    EXPECT_EQ(r.status, 3) << args << "\n" << r.output;
    const std::size_t at = args.find(" -") + 1;
    const std::string option = args.substr(at, args.find(' ', at) - at);
    EXPECT_TRUE(has(r.output, "option '" + option + "': unknown")) << r.output;
  }
  for (const std::string args : {"run --out", "eval memory d --json", "sim generate w --seed"}) {
    const Result r = runRasm(args);
    EXPECT_EQ(r.status, 3) << args << "\n" << r.output;
    EXPECT_TRUE(has(r.output, "option " + args.substr(args.rfind(' ') + 1) + ": expects a value"))
        << r.output;
  }
  // -v is rasm run's own --verbose (every log message); main keeps --verbose for run too.
  EXPECT_TRUE(has(runRasm("run -v --frobnicate").output, "'--frobnicate': unknown"));
}

TEST(Options, ManPageAndCompletionListEveryOption) {
  std::ostringstream man, completion;
  writeManPage(man);
  writeBashCompletion(completion);
  for (const auto& [name, info] : commands()) {
    const std::string word = name.substr(name.rfind(' ') + 1);
    EXPECT_TRUE(has(completion.str(), "    " + word + ")\n")) << name;
    EXPECT_TRUE(has(man.str(), ".B " + roffDashes(name) + "\n")) << name;
    for (const OptionDecl& o : info.decl.options) {
      EXPECT_TRUE(has(completion.str(), " --" + o.name + " ") ||
                  has(completion.str(), "\"--" + o.name + " "))
          << name << " --" << o.name;
      EXPECT_TRUE(has(man.str(), ".B " + roffDashes(optionLabel(o)) + "\n")) << name;
    }
  }
}
