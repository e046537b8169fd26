#include "rasm/surfel_map/SurfelFrameInserter.h"

#include <mutex>
#include <stdexcept>

namespace rasm::maps {

namespace {
std::mutex& factoryMutex() {
  static std::mutex m;
  return m;
}
SurfelFrameInserterFactory& factorySlot() {
  static SurfelFrameInserterFactory f;
  return f;
}
}  // namespace

void setSurfelFrameInserterFactory(SurfelFrameInserterFactory factory) {
  std::lock_guard<std::mutex> lock(factoryMutex());
  factorySlot() = std::move(factory);
}

std::unique_ptr<SurfelFrameInserter> makeSurfelFrameInserter(const std::string& fusion_ini_text,
                                                             const std::string& source) {
  SurfelFrameInserterFactory f;
  {
    std::lock_guard<std::mutex> lock(factoryMutex());
    f = factorySlot();
  }
  if (!f)
    throw std::logic_error(
        "CSurfelMap::insertObservation needs the fusion module: link rasm::fusion (it registers "
        "the "
        "surfel frame inserter when loaded)");
  return f(fusion_ini_text, source);
}

}  // namespace rasm::maps
