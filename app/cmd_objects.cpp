// `rasm objects <run folder>`: the objects a run found (its objects.json, section IV) as a table.
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "Command.h"
#include "RunObjects.h"
#include "rasm/core/Error.h"

namespace {

const char* kUsage =
    "usage: rasm objects <run folder> [--all]\n"
    "Prints <run folder>/objects.json: segment, class and probability, runner-up, surfels,\n"
    "detections fused, centroid and upright extents (m), zero-shot pose hint. With --all also its\n"
    "other_segments (classified segments that are not objects), with the reason: unconfirmed\n"
    "(no class reached min_object_probability), fragment (too few surfels or too small) or\n"
    "structure (a floor, wall or ceiling).\n";

double at(const nlohmann::json& v, int k) {
  return v.is_array() && int(v.size()) > k && v[k].is_number() ? v[k].get<double>() : 0.0;
}

int objects(const std::vector<std::string>& args) {
  std::string run;
  bool all = false;
  for (const std::string& a : args) {
    if (a == "--all")
      all = true;
    else if (a.rfind("--", 0) == 0)
      throw rasm::InputError("unknown option '" + a + "'\n" + kUsage);
    else
      run = a;
  }
  if (run.empty()) throw rasm::InputError(std::string("expected <run folder>\n") + kUsage);
  nlohmann::json objects = rasm::app::readRunObjects(run);
  const std::string path = (std::filesystem::path(run) / "objects.json").string();
  const std::size_t n_objects = objects.size();
  if (all)
    for (const auto& o : rasm::app::readRunOtherSegments(run)) objects.push_back(o);
  std::printf("%7s  %-16s %5s  %-16s %5s %8s %5s  %-22s %-18s %s\n", "segment", "class", "p",
              "runner-up", "p", "surfels", "dets", "centroid (m)", "extents (m)",
              all ? "pose hint / not an object" : "pose hint");
  int shown = 0;
  for (const auto& o : objects) {
    const std::string cls = o.value("class", "none");
    ++shown;
    const auto& c = o.contains("centroid") ? o["centroid"] : nlohmann::json();
    const auto& e = o.contains("oriented_box") ? o["oriented_box"]["extents_m"] : nlohmann::json();
    char pose[64] = "";
    if (o.contains("pose_hint"))
      std::snprintf(
          pose, sizeof pose, "%s az %.0f el %.0f", o["pose_hint"].value("class", "").c_str(),
          o["pose_hint"].value("azimuth_deg", 0.0), o["pose_hint"].value("elevation_deg", 0.0));
    if (o.contains("not_an_object"))
      std::snprintf(pose, sizeof pose, "(%s)", o.value("not_an_object", "").c_str());
    std::printf("%7u  %-16s %5.2f  %-16s %5.2f %8d %5d  %6.2f %6.2f %6.2f  %5.2f %5.2f %5.2f  %s\n",
                o.value("segment", 0u), cls.c_str(), o.value("probability", 0.5),
                o.value("runner_up", "none").c_str(), o.value("runner_up_probability", 0.5),
                o.value("surfels", 0), o.value("detections_fused", 0), at(c, 0), at(c, 1), at(c, 2),
                at(e, 0), at(e, 1), at(e, 2), pose);
  }
  std::printf("%zu objects, %d rows shown, in %s%s\n", n_objects, shown, path.c_str(),
              all ? "" : " (--all: also the classified segments that are not objects)");
  return 0;
}

const rasm::app::Registrar reg{"objects", "the objects of a run: rasm objects <run folder>",
                               &objects, kUsage};

}  // namespace
