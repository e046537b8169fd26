// `rasm help [command [subcommand] | outputs]`: the command list, a command's usage, or what every
// file, field and column of a run folder holds (rasm::pipeline::outputsDocumentation, built from
// the assembled Mapper's stage list; docs/outputs.md is its output).
#include <iostream>

#include "Command.h"
#include "ShellDocs.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/OutputsDoc.h"

namespace {

const char* kUsage =
    "usage: rasm help                      the commands\n"
    "       rasm help <command> [sub]      a command's usage (= rasm <command> [sub] --help)\n"
    "       rasm help outputs              every file of a run folder, every report.json field\n"
    "                                      and frames.csv column (Markdown; docs/outputs.md)\n"
    "       rasm help man                  the man page rasm(1) (roff, as man reads it)\n"
    "       rasm help completion           a bash completion script (source it, or install it\n"
    "                                      as share/bash-completion/completions/rasm)\n";

int helpMain(const std::vector<std::string>& args) {
  using namespace rasm::app;
  if (args.empty()) {
    printCommandList(std::cout);
    return 0;
  }
  if (args[0] == "outputs") {
    if (args.size() > 1)
      rasm::throwInputError("argument '" + args[1] + "'", "unexpected after rasm help outputs");
    std::cout << rasm::pipeline::outputsDocumentation(rasm::pipeline::Mapper());
    return 0;
  }
  if (args[0] == "man" || args[0] == "completion") {
    if (args.size() > 1)
      rasm::throwInputError("argument '" + args[1] + "'", "unexpected after rasm help " + args[0]);
    if (args[0] == "man")
      writeManPage(std::cout);
    else
      writeBashCompletion(std::cout);
    return 0;
  }
  const auto it = commands().find(args[0]);
  if (it == commands().end())
    rasm::throwInputError("rasm help " + args[0],
                          "unknown: expected a command (rasm help lists them), outputs, man or "
                          "completion");
  const std::string usage =
      usageOf(args[0], std::vector<std::string>(args.begin() + 1, args.end()));
  if (!usage.empty()) {
    std::cout << usage;
    return 0;
  }
  return it->second.fn({"--help"});  // the command prints its own usage
}

const rasm::app::Registrar reg("help",
                               "the commands, a command's usage, or: rasm help outputs | man | "
                               "completion",
                               helpMain, kUsage);

}  // namespace
