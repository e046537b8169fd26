#include "rasm/io/EvaluationJson.h"

namespace rasm::io {

nlohmann::json toJson(const ErrorStats& s) {
  return {{"count", s.count}, {"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
          {"std", s.std},     {"min", s.min},   {"max", s.max}};
}

nlohmann::json toJson(const AteResult& r, const AteOptions& opt) {
  nlohmann::json j;
  j["metric"] = "ate";
  j["pairs"] = r.translation_m.count;
  j["translation_m"] = toJson(r.translation_m);
  j["options"] = {{"max_dt_s", opt.max_dt_s},
                  {"offset_s", opt.offset_s},
                  {"align", opt.align},
                  {"scale", opt.scale}};
  const Eigen::Matrix4d M = r.T_gt_est.matrix();
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 4; ++i) rows.push_back({M(i, 0), M(i, 1), M(i, 2), M(i, 3)});
  j["alignment"] = {{"T_gt_est", rows}, {"scale", r.scale}};
  return j;
}

nlohmann::json toJson(const RpeResult& r, const RpeOptions& opt) {
  nlohmann::json j;
  j["metric"] = "rpe";
  j["pairs"] = r.pairs;
  j["delta"] = opt.delta;
  j["delta_unit"] = opt.delta_in_frames ? "frames" : "s";
  j["offset_s"] = opt.offset_s;
  j["translation_m"] = toJson(r.translation_m);
  j["rotation_deg"] = toJson(r.rotation_deg);
  return j;
}

}  // namespace rasm::io
