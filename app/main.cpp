// rasm: rapid autonomous semantic mapping. `rasm <command> [args]`; `rasm help` lists commands.
#include <unistd.h>

#include <cstdlib>
#include <exception>
#include <iostream>

#include "Command.h"
#include "rasm/core/Error.h"

int main(int argc, char** argv) {
  // libgomp reads OMP_WAIT_POLICY when it is loaded, before main. Its default (spin for a while
  // before sleeping) makes every parallel region wait for descheduled threads whenever another
  // process or thread competes for the 2 cores of a robot laptop: measured 2-2.5x slower frames
  // on TUM fr1/xyz. Unless the user chose a policy, re-execute once with the passive one.
  if (!std::getenv("OMP_WAIT_POLICY") && !std::getenv("RASM_NO_REEXEC")) {
    ::setenv("OMP_WAIT_POLICY", "passive", 1);
    ::setenv("RASM_NO_REEXEC", "1", 1);
    ::execv("/proc/self/exe", argv);  // returns only on failure: then go on with the default
  }
  using namespace rasm::app;
  const auto& cmds = commands();
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    printCommandList(std::cout);
    return argc < 2 ? 1 : 0;
  }
  const std::string name = std::string(argv[1]) == "--version" ? "version" : argv[1];
  const auto it = cmds.find(name);
  if (it == cmds.end()) {
    std::cerr << "rasm: unknown command '" << argv[1] << "' (try `rasm help`)\n";
    return 2;
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  if (const std::string usage = usageOf(name, args); !usage.empty() && wantsHelp(args)) {
    std::cout << usage;
    return 0;
  }
  try {
    return it->second.fn(args);
  } catch (const rasm::InputError& e) {
    std::cerr << "rasm " << name << ": error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "rasm " << name << ": failed: " << e.what() << "\n";
    return 4;
  }
}
