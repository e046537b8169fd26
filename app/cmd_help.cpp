// `rasm help [command [subcommand] | outputs]`: the command list, a command's usage, or what every
// file, field and column of a run folder holds (rasm::run::outputsDocumentation, built from
// the assembled Mapper's stage list; docs/outputs.md is its output).
#include <iostream>

#include "Command.h"
#include "ShellDocs.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/run/OutputsDoc.h"

namespace {

const rasm::app::CommandDecl kDecl{
    "help",
    "the commands, a command's usage, or: rasm help outputs | man | completion",
    {{"topic", "a command [and subcommand], outputs, man or completion", false, true}},
    {},
    "rasm help                      the commands\n"
    "rasm help <command> [sub]      a command's usage (= rasm <command> [sub] --help)\n"
    "rasm help outputs              every file of a run folder, every report.json field\n"
    "                               and frames.csv column (Markdown; docs/outputs.md)\n"
    "rasm help man                  the man page rasm(1) (roff, as man reads it)\n"
    "rasm help completion           a bash completion script (source it, or install it\n"
    "                               as share/bash-completion/completions/rasm)\n"};

int helpMain(const rasm::app::ParsedArgs& parsed) {
  using namespace rasm::app;
  const std::vector<std::string> topic = parsed.positionals("topic");
  if (topic.empty()) {
    printCommandList(std::cout);
    return 0;
  }
  if (topic[0] == "outputs" || topic[0] == "man" || topic[0] == "completion") {
    if (topic.size() > 1)
      rasm::throwInputError("argument '" + topic[1] + "'",
                            "unexpected after rasm help " + topic[0]);
    if (topic[0] == "outputs")
      std::cout << rasm::run::outputsDocumentation(rasm::pipeline::Mapper());
    else if (topic[0] == "man")
      writeManPage(std::cout);
    else
      writeBashCompletion(std::cout);
    return 0;
  }
  std::vector<std::string> rest;
  const CommandInfo* info =
      topic[0].find(' ') == std::string::npos
          ? resolveCommand(topic[0], std::vector<std::string>(topic.begin() + 1, topic.end()), rest)
          : nullptr;
  if (!info)
    rasm::throwInputError("rasm help " + topic[0],
                          "unknown: expected a command (rasm help lists them), outputs, man or "
                          "completion");
  std::cout << usageOf(info->decl);
  return 0;
}

const rasm::app::Registrar reg{kDecl, &helpMain};

}  // namespace
