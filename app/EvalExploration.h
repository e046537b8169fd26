#pragma once
// `rasm eval exploration <run folder>...`: the exploration table (issue 18, deliverable 7) from
// the report.json and exploration.json of exploring runs (app/cmd_eval_exploration.cpp).
#include <string>
#include <vector>

namespace rasm::app {
int evalExploration(const std::vector<std::string>& args);
}
