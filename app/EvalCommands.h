#pragma once
// `rasm eval` subcommands that live in their own files (app/cmd_eval.cpp dispatches):
// `rasm eval exploration <run folder>...`: the exploration table from
// the report.json and exploration.json of exploring runs (app/cmd_eval_exploration.cpp);
// `rasm eval memory <run folder>`: the memory curve of a run and whether it plateaus
// (app/cmd_eval_memory.cpp).
#include <string>
#include <vector>

namespace rasm::app {
int evalExploration(const std::vector<std::string>& args);
int evalMemory(const std::vector<std::string>& args);
}
