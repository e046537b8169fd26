// `rasm objects <run folder>`: the objects a run found (its objects.json, section IV) as a table.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "Command.h"
#include "RunObjects.h"
#include "rasm/core/Error.h"

namespace {

const rasm::app::CommandDecl kDecl{
    "objects",
    "the objects of a run: rasm objects <run folder>",
    {{"run folder", "the output folder of a `rasm run` (its objects.json)"}},
    {{"all", "", "also the classified segments that are not objects, with the reason"}},
    "Prints <run folder>/objects.json: each object once: its id, class and probability,\n"
    "runner-up, existence probability (views detected / views), surfels, detections fused, the\n"
    "frames it was seen in (count, first-last), centroid and upright extents (m), its segments "
    "and\n"
    "the zero-shot pose hint. With --all also its other_segments (classified segments that are\n"
    "not part of a reported object, with their object's id), with the reason: unconfirmed (no\n"
    "class reached min_object_probability), fragment (too few surfels or too small), structure (a\n"
    "floor, wall or ceiling) or rarely_detected (detected in too few of the views that should\n"
    "have).\n"};

double at(const nlohmann::json& v, int k) {
  return v.is_array() && int(v.size()) > k && v[k].is_number() ? v[k].get<double>() : 0.0;
}

/// "3,7,12" (a run folder before the object layer: its one `segment`).
std::string segmentList(const nlohmann::json& o, const std::string& path) {
  std::string out;
  for (const std::uint32_t s : rasm::app::objectSegments(o, path))
    out += (out.empty() ? "" : ",") + std::to_string(s);
  return out;
}

void printRow(const nlohmann::json& o, const std::string& path) {
  const auto& c = o.contains("centroid") ? o["centroid"] : nlohmann::json();
  const auto& e = o.contains("oriented_box") ? o["oriented_box"]["extents_m"] : nlohmann::json();
  const auto& f = o.contains("frames") ? o["frames"] : nlohmann::json::object();
  char frames[48] = "";
  if (f.contains("seen"))
    std::snprintf(frames, sizeof frames, "%d %zu-%zu", f.value("seen", 0),
                  f.value("first_seen", std::size_t(0)), f.value("last_seen", std::size_t(0)));
  char exist[16] = "";
  if (o.contains("existence_probability"))
    std::snprintf(exist, sizeof exist, "%.2f", o.value("existence_probability", 0.0));
  std::string note;
  if (o.contains("pose_hint")) {
    char pose[64];
    std::snprintf(
        pose, sizeof pose, "%s az %.0f el %.0f", o["pose_hint"].value("class", "").c_str(),
        o["pose_hint"].value("azimuth_deg", 0.0), o["pose_hint"].value("elevation_deg", 0.0));
    note = pose;
  }
  if (o.contains("not_an_object")) note = "(" + o.value("not_an_object", std::string()) + ")";
  const int id = o.contains("id") ? o.value("id", 0) : o.value("object", 0);
  std::printf(
      "%6d  %-16s %5.2f  %-16s %5.2f %5s %8d %5d %-14s %6.2f %6.2f %6.2f  %5.2f %5.2f %5.2f"
      "  %-12s %s\n",
      id, o.value("class", "none").c_str(), o.value("probability", 0.5),
      o.value("runner_up", "none").c_str(), o.value("runner_up_probability", 0.5), exist,
      o.value("surfels", 0), o.value("detections_fused", 0), frames, at(c, 0), at(c, 1), at(c, 2),
      at(e, 0), at(e, 1), at(e, 2), segmentList(o, path).c_str(), note.c_str());
}

int objects(const rasm::app::ParsedArgs& args) {
  const std::string run = args.positional("run folder");
  const bool all = args.has("all");
  nlohmann::json objects = rasm::app::readRunObjects(run);
  const std::string path = (std::filesystem::path(run) / "objects.json").string();
  const std::size_t n_objects = objects.size();
  if (all)
    for (const auto& o : rasm::app::readRunOtherSegments(run)) objects.push_back(o);
  std::printf("%6s  %-16s %5s  %-16s %5s %5s %8s %5s %-14s %-20s %-17s  %-12s %s\n", "object",
              "class", "p", "runner-up", "p", "exist", "surfels", "dets", "frames seen",
              "centroid (m)", "extents (m)", "segments",
              all ? "pose hint / not an object" : "pose hint");
  for (const auto& o : objects) printRow(o, path);
  std::printf("%zu objects, %zu rows shown, in %s%s\n", n_objects, objects.size(), path.c_str(),
              all ? "" : " (--all: also the classified segments that are not objects)");
  return 0;
}

const rasm::app::Registrar reg{kDecl, &objects};

}  // namespace
