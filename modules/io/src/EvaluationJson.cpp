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

nlohmann::json toJson(const WorldFrameError& r, const WorldFrameOptions& opt) {
  nlohmann::json j;
  j["metric"] = "world_frame_error";
  j["pairs"] = r.position_m.count;
  j["position_m"] = toJson(r.position_m);
  j["vertical_m"] = toJson(r.vertical_m);
  j["horizontal_m"] = toJson(r.horizontal_m);
  j["tilt_deg"] = toJson(r.tilt_deg);
  j["heading_deg"] = toJson(r.heading_deg);
  j["start_error"] = {{"position_m", r.start_position_error_m},
                      {"rotation_deg", r.start_rotation_error_deg}};
  j["options"] = {{"max_dt_s", opt.max_dt_s},
                  {"up_world", {opt.up_world.x(), opt.up_world.y(), opt.up_world.z()}}};
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
