#pragma once
// The map proper, as the exploration loop measures it and SimObjectScore scores it.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace rasm::maps {
class CSurfelMap;
}

namespace rasm::autonomy {

/// The map proper: its alive, stable surfels (unstable ones come and go, II-B), their positions
/// (world frame, m) and segment ids, index by index.
struct StableSurfels {
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::uint32_t> segment;
};
StableSurfels stableSurfels(const maps::CSurfelMap& map);

}  // namespace rasm::autonomy
