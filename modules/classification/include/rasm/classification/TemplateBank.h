#pragma once
// Training of the zero-shot classifier (paper IV-A): "orthographic views of the geometric model
// are rendered from different viewpoints, at 5 degree increments in azimuth and elevation. If
// model dimensions are parameterized, multiple images can be rendered from each viewpoint for
// different combination of parameter values. Images are scaled down to 16 x 16 resolution
// templates ... HOG features are precomputed for each of the rendered templates."
//
// Models file (YAML; relative mesh paths are relative to the file's folder):
//
//   views:                        # optional; the values shown are the defaults
//     azimuth_step_deg: 5         # azimuths 0, 5, ..., < 360 / azimuth_symmetry
//     elevation_deg: [-10, 60]    # first and last elevation (inclusive), |e| < 90
//     elevation_step_deg: 5
//     render_px: 64               # square canvas of the rendering, downscaled to 16 x 16
//   models:
//     - class: conference_phone   # class name the detections carry
//       procedural: conference_phone   # rasm::models::makeProceduralModel name, or
//       azimuth_symmetry: 3       # optional: the model looks the same every 360/3 degrees
//     - class: mug
//       mesh: models/mug.obj      # any assimp format (rasm::models::loadMesh), model frame z up
//       scale: 0.001              # optional: one factor or [sx, sy, sz]
//     - class: cabinet
//       box:                      # a box of unknown dimensions: [min, max, steps] per axis (m)
//         x: [0.3, 1.2, 4]        # steps values from min to max (steps = 1: min only)
//         y: [0.3, 1.2, 4]
//         z: [0.3, 1.2, 4]
//       azimuth_symmetry: 2
//
// Several entries may share a class (e.g. two mug models). Views are orthographic, so a template
// depends on the dimensions only through their ratios: box combinations proportional to an earlier
// one (0.3 x 0.3 x 0.3 and 0.6 x 0.6 x 0.6) would render identical templates and are skipped.
//
// Rendering (renderTemplateView): a z-buffered orthographic rasteriser over the mesh triangles,
// flat Lambertian shading (two-sided) under a light fixed relative to the camera, on a black
// background. The outline (object against background) and the creases between differently lit
// faces are the gradients HOG sees; HOG's unsigned orientations make the template independent of
// whether the real object is darker or brighter than its background.
//
// Descriptor (describePatch): cv::HOGDescriptor on the 16 x 16 patch, winSize 16, blockSize 8,
// blockStride 4, cellSize 4, 9 unsigned bins (Dalal & Triggs' block layout scaled to the 16 px
// window): 3 x 3 blocks x 4 cells x 9 bins = 324 values, L2-normalised, so that the cosine
// similarity of IV-A is a dot product. The object fills kTemplateObjectPx of the kTemplatePx
// pixels (a 1 px border so the outline's gradient lies inside the window); proposals are cropped
// the same way (squareCropWithMargin).

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "rasm/models/Mesh.h"

namespace rasm::classification {

constexpr int kTemplatePx = 16;        ///< IV-A: 16 x 16 templates
constexpr int kTemplateObjectPx = 14;  ///< longer side of the object inside the template

/// The view grid of training (the models file's `views:` block).
struct TemplateViews {
  float azimuth_step_deg = 5.f;  ///< IV-A: 5 degree increments
  float elevation_min_deg = -10.f;
  float elevation_max_deg = 60.f;
  float elevation_step_deg = 5.f;
  int render_px = 64;
};

/// One entry of the models file.
struct ModelSpec {
  std::string class_name;
  std::string source;  ///< "procedural:<name>", "mesh:<path>" or "box" (for messages and the bank)
  models::TriangleMesh mesh;  ///< procedural or mesh models (scale applied); empty for a box
  /// Box dimensions per axis: values[axis] = the dimensions tried (m). Empty for mesh models.
  std::vector<float> box_values[3];
  int azimuth_symmetry = 1;
};

struct ModelsSpec {
  std::string path;  ///< the YAML file (for messages)
  TemplateViews views;
  std::vector<ModelSpec> models;
};

/// Parses a models file; throws InputError "<file>: models[i].<key>: <problem>" (a missing mesh
/// names the mesh file).
ModelsSpec loadModelsSpec(const std::string& yaml_path);

/// What one template was rendered from.
struct TemplateInfo {
  int class_index = 0;
  int model_index = 0;  ///< entry of the models file
  float azimuth_deg = 0.f;
  float elevation_deg = 0.f;
  Eigen::Vector3f dimensions_m = Eigen::Vector3f::Zero();  ///< box combination (0 for meshes)
  float aspect = 1.f;  ///< width / height of the object's outline in the rendered view
};

struct TemplateBank {
  std::vector<std::string> class_names;
  std::vector<std::string> model_sources;  ///< ModelSpec::source of each model index
  TemplateViews views;
  std::vector<TemplateInfo> templates;
  cv::Mat descriptors;  ///< CV_32F, one L2-normalised descriptor per template row

  std::size_t size() const { return templates.size(); }
  int classIndex(const std::string& name) const;  ///< -1 when absent
  std::size_t templatesOfClass(int class_index) const;
};

/// The azimuth period of a model of the bank (360 / its azimuth_symmetry): the largest azimuth
/// rendered for it plus one azimuth step, as the nearest divisor of 360.
float modelAzimuthPeriodDeg(const TemplateBank& bank, int model_index);

/// Called after each model with (model index, models total, templates so far).
using TrainingProgress = std::function<void(std::size_t, std::size_t, std::size_t)>;

/// Renders every view of every model and computes the descriptors. Deterministic: the same spec
/// gives the same bank bit for bit, whatever the number of threads.
TemplateBank trainTemplateBank(const ModelsSpec& spec, const TrainingProgress& progress = {});

/// Binary bank file (little-endian): magic "RASMZSC1", the views, class names, model sources,
/// the template table and the descriptor matrix. save writes <path>.tmp and renames it.
void saveTemplateBank(const TemplateBank& bank, const std::string& path);
/// Throws InputError naming `path` when the file is missing, not a bank or truncated.
TemplateBank loadTemplateBank(const std::string& path);

/// Orthographic, shaded view (CV_8UC1, render_px square) of `mesh` from the camera direction at
/// azimuth (about z from +x) and elevation (above the xy plane) in the model frame; the outline's
/// longer side spans render_px * kTemplateObjectPx / kTemplatePx pixels, centred. `aspect`
/// (optional) receives the outline's width / height.
cv::Mat renderTemplateView(const models::TriangleMesh& mesh, float azimuth_deg, float elevation_deg,
                           int render_px, float* aspect = nullptr);

/// Length of the descriptor of one 16 x 16 patch (324).
int descriptorLength();
/// HOG of a kTemplatePx square patch (CV_8UC1 or CV_8UC3), L2-normalised, into `out`
/// (descriptorLength() floats).
void describePatch(const cv::Mat& patch, float* out);
/// The square kTemplatePx patch of `image` around `box`, with the template's margin: a square of
/// side max(w, h) * kTemplatePx / kTemplateObjectPx centred on the box, outside the image
/// replicated from the border, area-averaged down.
cv::Mat squareCropWithMargin(const cv::Mat& image, const cv::Rect& box);

}  // namespace rasm::classification
