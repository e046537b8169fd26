#include "rasm/autonomy/StableSurfels.h"

#include "rasm/surfel_map/CSurfelMap.h"

namespace rasm::autonomy {

StableSurfels stableSurfels(const maps::CSurfelMap& map) {
  const maps::SurfelArrays a = map.store().arrays();
  StableSurfels out;
  out.positions.reserve(std::size_t(a.size));
  out.segment.reserve(std::size_t(a.size));
  for (int i = 0; i < a.size; ++i)
    if (a.alive(i) && a.stable(i)) {
      out.positions.push_back(a.position(i));
      out.segment.push_back(a.segment[i]);
    }
  return out;
}

}  // namespace rasm::autonomy
