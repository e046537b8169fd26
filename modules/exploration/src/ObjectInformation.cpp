#include "rasm/exploration/ObjectInformation.h"

#include <cmath>

#include "rasm/fusion/TFusionParams.h"
#include "rasm/surfel_map/kernels/ViewBins.h"

namespace rasm::exploration {

ViewInfoModel ViewInfoModel::of(const fusion::TFusionParams& fusion,
                                const maps::SurfelStoreOptions& map) {
  ViewInfoModel m;
  m.lambda1 = fusion.ic_lambda1;
  m.d_min_m = fusion.ic_d_min_m;
  m.n_azimuth = map.view_bins_azimuth;
  m.n_elevation = map.view_bins_elevation;
  return m;
}

float classUncertaintyWeight(const maps::ClassEvidence& evidence, float floor) {
  if (maps::classEvidenceEmpty(evidence)) return floor;
  const float p_best = maps::bestClass(evidence).probability;
  const float u = 1.0f - std::fabs(2.0f * p_best - 1.0f);
  return u > floor ? u : floor;
}

InformationGain predictedInformationGain(const maps::SurfelStore& store,
                                         const Image<std::int32_t>& index,
                                         const Eigen::Isometry3d& T_world_cam,
                                         const ViewInfoModel& model, float weight_floor) {
  InformationGain g;
  const maps::SurfelArrays s = store.arrays();
  if (s.n_view_bins <= 0) return g;
  const Vec3f t = T_world_cam.translation().cast<float>();
  for (int y = 0; y < index.height(); ++y)
    for (int x = 0; x < index.width(); ++x) {
      const int i = index(x, y);
      if (i < 0 || i >= s.size) continue;
      ++g.pixels;
      // V-B, as fusion's updateViewBin: bin of the direction to the camera, IC of the distance.
      const Vec3f d = t - s.position(i);
      const float dist = d.norm();
      if (!(dist > 0.0f)) continue;
      const int bin = maps::kernels::viewBinIndex(s.normal(i), s.basis[i], d * (1.0f / dist),
                                                  model.n_azimuth, model.n_elevation);
      const int ic_new =
          maps::quantizeUnit(maps::kernels::informationContent(dist, model.lambda1, model.d_min_m));
      const int gain = ic_new - int(s.viewRow(i)[bin]);
      if (gain <= 0) continue;
      const double bin_gain = double(gain) / 255.0;
      const float u =
          s.class_ev ? classUncertaintyWeight(s.class_ev[i], weight_floor) : weight_floor;
      g.unweighted += bin_gain;
      g.weighted += double(u) * bin_gain;
    }
  return g;
}

}  // namespace rasm::exploration
