// rasm: rapid autonomous semantic mapping. `rasm <command> [args]`; `rasm help` lists commands.
#include <exception>
#include <iostream>

#include "Command.h"
#include "rasm/core/Error.h"

int main(int argc, char** argv) {
  using namespace rasm::app;
  const auto& cmds = commands();
  if (argc < 2 || std::string(argv[1]) == "help" || std::string(argv[1]) == "--help" ||
      std::string(argv[1]) == "-h") {
    std::cout << "usage: rasm <command> [args]\n\ncommands:\n";
    for (const auto& [name, info] : cmds) std::cout << "  " << name << "\t" << info.help << "\n";
    return argc < 2 ? 1 : 0;
  }
  const auto it = cmds.find(argv[1]);
  if (it == cmds.end()) {
    std::cerr << "rasm: unknown command '" << argv[1] << "' (try `rasm help`)\n";
    return 2;
  }
  try {
    return it->second.fn(std::vector<std::string>(argv + 2, argv + argc));
  } catch (const rasm::InputError& e) {
    std::cerr << "rasm " << argv[1] << ": error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "rasm " << argv[1] << ": failed: " << e.what() << "\n";
    return 4;
  }
}
