// libFuzzer target: the simulator's YAML loaders (rasm::sim::loadWorldFromString: worlds with
// primitives, meshes by name, materials, lights; the first byte odd: a trajectory spec instead,
// rasm::sim::loadTrajectorySpecFromString when built).
#include <cstdint>

#include "FuzzUtil.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/World.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  rasm::fuzz::expectOnlyInputErrors([&] {
    if (data[0] & 1)
      (void)rasm::sim::loadTrajectorySpecFromString(text, "fuzz.yaml");
    else
      (void)rasm::sim::loadWorldFromString(text, "fuzz.yaml", "");
  });
  return 0;
}
