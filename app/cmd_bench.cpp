// rasm bench <file.ini | rawlog | dataset folder> [--frames N] [--preload] [--set s.k=v ...]
// Runs the mapping front end without map outputs and prints one JSON object on stdout:
// frames per second, per-stage mean/max ms, surfels, map bytes, peak RSS. Benchmarks are never
// part of the unit tests. --preload decodes every frame before the clock starts ([source] preload):
// the frame rate then measures the mapping alone, as fed by a live camera. The run's small files
// (config.ini, frames.csv, report.json, ...) go to a folder of its own made by mkdtemp in $TMPDIR
// (rasm::ScratchFolder), removed at the end, also when SIGINT / SIGTERM stops it (exit 128 + the
// signal; the frames done are reported).
#include <cstdio>
#include <iostream>

#include "Command.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/Interrupts.h"
#include "rasm/run/MappingRun.h"

namespace {

const rasm::app::CommandDecl kDecl{
    "bench",
    "frame rate and per-stage ms as JSON: rasm bench <ini|rawlog|folder> [--frames N] [--preload]",
    {{"file.ini | rawlog | dataset folder",
      "what to map (default: the embedded default on its scripted path)", false}},
    {{"frames", "N", "stop after N frames ([source] max_frames)"},
     {"preload", "", "decode every frame before the clock starts ([source] preload)"},
     {"set", "section.key=value", "set one key of the configuration", "", true}},
    "Maps without writing map outputs and prints one JSON object: frames/s, per-stage mean/max\n"
    "ms, surfels, map bytes, peak RSS (report.json's fields). Without an input: the embedded\n"
    "default on its scripted path (no exploration). --preload decodes every frame first.\n"};

/// The configuration overrides the options stand for, in the order given.
std::vector<std::string> overridesOf(const rasm::app::ParsedArgs& args) {
  std::vector<std::string> overrides;
  for (const auto& [option, value] : args.given()) {
    if (option == "frames")
      overrides.push_back("source.max_frames=" + value);
    else if (option == "preload")
      overrides.push_back("source.preload=true");
    else if (option == "set")
      overrides.push_back(value);
  }
  return overrides;
}

int benchMain(const rasm::app::ParsedArgs& args) {
  using namespace rasm::pipeline;
  using namespace rasm::run;
  const std::string input = args.positional(kDecl.positionals[0].name);
  const std::vector<std::string> overrides = overridesOf(args);
  RunConfig cfg = RunConfig::embeddedDefault();
  if (!input.empty()) {
    if (input.size() > 4 && input.substr(input.size() - 4) == ".ini") {
      cfg = RunConfig::fromFile(input);
    } else {
      cfg.set("source", "type", "auto");
      cfg.set("source", "path", input);
    }
  }
  // The mapping pipeline's speed: the embedded default's robot follows its scripted path
  // (--set exploration.enabled=auto explores, with the planner's pauses in the timings).
  cfg.set("exploration", "enabled", "false");
  for (const char* k : {"write_ply", "write_3dscene", "save_map", "preview_png", "write_rawlog"})
    cfg.set("output", k, "false");
  for (const auto& o : overrides) cfg.applyOverride(o);
  // After the overrides: the scratch folder is the bench's own (no --set output.dir).
  // SIGINT / SIGTERM: the run stops after its frame and returns, and the scratch folder goes
  // with `scratch`; a second signal aborts at once and the handler removes the folder.
  installInterruptHandlers();
  const rasm::ScratchFolder scratch("rasm_bench_");
  const ScopedAbortRemovesFolder remove_on_abort(scratch.path());
  cfg.set("output", "dir", scratch.path());
  MappingRun run(cfg);
  const RunSummary s = run.run();
  nlohmann::json j = s.report;
  j["bench"] = "mapping";
  j["input"] = input.empty() ? "embedded default" : input;
  std::cout << j.dump() << std::endl;
  return stopSignal() != 0 ? 128 + stopSignal() : 0;
}

const rasm::app::Registrar reg{kDecl, &benchMain};

}  // namespace
