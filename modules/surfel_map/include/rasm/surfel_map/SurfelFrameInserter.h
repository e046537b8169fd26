#pragma once
// Dependency inversion for CSurfelMap::insertObservation(): fusion (II-B, II-D) lives in the
// fusion module, which comes after surfel_map in the module order, so the map cannot call it
// directly. The fusion library registers a factory when it is loaded (an MRPT_INITIALIZER in
// modules/fusion/src/FusionInserter.cpp); CSurfelMap creates its inserter lazily through it.
// A program that inserts observations into a CSurfelMap must therefore link rasm::fusion.

#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <string>

#include "rasm/core/RgbdFrame.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::maps {

class SurfelFrameInserter {
 public:
  virtual ~SurfelFrameInserter() = default;
  /// Fuses `frame` into `map` at the known camera pose T_world_cam (optical frame), no tracking.
  virtual void insertFrame(SurfelStore& map, const RgbdFrame& frame,
                           const Eigen::Isometry3d& T_world_cam) = 0;
};

/// Builds an inserter from INI text holding a `[fusion]` section (may be empty: defaults).
/// `source` names where the text came from, for error messages. Throws InputError on bad keys.
using SurfelFrameInserterFactory = std::function<std::unique_ptr<SurfelFrameInserter>(
    const std::string& fusion_ini_text, const std::string& source)>;

void setSurfelFrameInserterFactory(SurfelFrameInserterFactory factory);
/// Throws std::logic_error ("... link rasm::fusion ...") when no factory is registered.
std::unique_ptr<SurfelFrameInserter> makeSurfelFrameInserter(const std::string& fusion_ini_text,
                                                             const std::string& source);

}  // namespace rasm::maps
