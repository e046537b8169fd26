#pragma once
// Map export: PLY point clouds and MRPT .3Dscene files of the surfel map (DESIGN.md "Outputs of a
// run"). They live in surfel_map rather than io because io precedes surfel_map in the module
// order (DESIGN.md "Layout"): io cannot see the map, the map can see everything io sees.
//
// PLY layout (binary_little_endian 1.0, one element `vertex` per surfel):
//   float x y z            position (world, m)
//   float nx ny nz         unit normal (world)
//   uchar red green blue   colour
//   float radius           m
//   float confidence       w
//   int   segment          l (0 = none)
//   int   class            best class id (ClassEvidence.h bestClass: 1..80 COCO, 81.. project),
//                          0 when n_classes = 0 or no class rose above the 0.5 prior
//   float class_probability  p of that class (0.5 when class = 0)
//   uchar stable           0/1
// MeshLab / CloudCompare / Open3D read it (radius, confidence, ... as scalar fields). Integer ids
// are `int` (int32): Open3D's tensor reader (o3d.t.io) drops `uint` columns. The reader also
// takes the layout before that change (`uint segment`, `uchar class`).

#include <memory>
#include <string>
#include <vector>

#include "rasm/surfel_map/SurfelStore.h"

namespace mrpt::opengl {
class CSetOfObjects;
class COpenGLScene;
}  // namespace mrpt::opengl

namespace rasm::maps {

/// How surfels are coloured in visualizations.
enum class SurfelColouring : int {
  Rgb = 0,         ///< measured colour
  Segment = 1,     ///< a distinct pseudo-colour per segment label (grey = none)
  Class = 2,       ///< a pseudo-colour per best class, faded to grey as p falls to 0.5 (none)
  Confidence = 3,  ///< blue (low) .. red (>= stable threshold reached: flag set)
  Stability = 4,   ///< green stable, red unstable
};

struct SurfelVisualOptions {
  SurfelColouring colouring = SurfelColouring::Rgb;
  float point_size = 2.0f;
  bool stable_only = false;
  float min_confidence = 0.0f;
};

/// Best class of surfel i and its probability (ClassEvidence.h bestClass); id 0, p 0.5 when the map
/// has no classes or no class of the surfel is above the 0.5 prior.
BestClass bestClass(const SurfelArrays& a, int i);

/// Pseudo-colour for a label (segment or class id); grey for <= 0 (segment) / < 0 (class).
Bgr8 labelColour(long long label);
/// The class map's colour (IV, the paper's Fig. 5 bottom): the class's labelColour, faded to
/// the "none" grey as its probability falls to the 0.5 prior.
Bgr8 classColour(const BestClass& best);

/// Writes the PLY described above; red/green/blue hold the measured colour, or with `colouring`
/// a visualization colour (e.g. Segment: one pseudo-colour per segment, map_segments.ply). Throws
/// InputError naming the path when it cannot be written.
void writeSurfelPly(const SurfelStore& map, const std::string& path, bool stable_only = false,
                    SurfelColouring colouring = SurfelColouring::Rgb);

/// What a PLY written by writeSurfelPly holds, per surfel (for tests and tools).
struct PlySurfels {
  std::vector<Vec3f> position, normal;
  std::vector<Bgr8> colour;
  std::vector<float> radius, confidence;
  std::vector<std::uint32_t> segment;
  std::vector<int> class_id;  ///< 0 = none
  std::vector<float> class_probability;
  std::vector<std::uint8_t> stable;
  std::size_t size() const { return position.size(); }
};
/// Reads a PLY with exactly the layout above (or the earlier one with `uint segment`, `uchar
/// class`); throws InputError naming the path otherwise.
PlySurfels readSurfelPly(const std::string& path);

/// Appends a coloured point cloud (mrpt::opengl::CPointCloudColoured, one point per surfel) to `o`.
void surfelsToOpenGL(const SurfelStore& map, const SurfelVisualOptions& opt,
                     mrpt::opengl::CSetOfObjects& o);

/// The scene of a .3Dscene: the coloured cloud and a grid.
std::shared_ptr<mrpt::opengl::COpenGLScene> surfelScene(const SurfelStore& map,
                                                        const SurfelVisualOptions& opt = {});

/// Saves surfelScene (mrpt::opengl::COpenGLScene::saveToFile); SceneViewer3D opens it. Throws
/// InputError naming the path on failure (MRPT does not check the last gzip flush: `rasm run`
/// writes its scenes through pipeline::writeGzArchive instead).
void writeSurfelScene(const SurfelStore& map, const std::string& path,
                      const SurfelVisualOptions& opt = {});

}  // namespace rasm::maps
