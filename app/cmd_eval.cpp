// `rasm eval ate|rpe`: TUM benchmark trajectory metrics (rasm::io::TrajectoryEvaluator).
#include <cstdio>
#include <fstream>
#include <iostream>

#include "Command.h"
#include "rasm/core/Error.h"
#include "rasm/io/EvaluationJson.h"
#include "rasm/io/TrajectoryEvaluator.h"

namespace {

const char* kUsage =
    "usage: rasm eval ate <groundtruth.txt> <estimate.txt> [--no-align | --scale] [--max-dt S]\n"
    "                     [--offset S] [--json out.json]\n"
    "       rasm eval rpe <groundtruth.txt> <estimate.txt> [--delta D] [--frames] [--offset S]\n"
    "                     [--json out.json]\n"
    "Trajectories in TUM format (timestamp tx ty tz qx qy qz qw). ATE aligns the estimate to the\n"
    "ground truth (Horn/Umeyama, SE(3); --scale: Sim(3)); RPE uses intervals of D s (default 1) "
    "or\n"
    "D frames (--frames).\n";

double parseNumber(const std::string& opt, const std::string& text) {
  try {
    std::size_t n = 0;
    const double v = std::stod(text, &n);
    if (n == text.size()) return v;
  } catch (const std::exception&) {
  }
  rasm::throwInputError(opt, "'" + text + "' is not a number");
}

void printStats(const char* name, const char* unit, const rasm::io::ErrorStats& s) {
  std::printf(
      "  %-12s %-5s rmse %10.6f  mean %10.6f  median %10.6f  std %10.6f  min %10.6f  max %10.6f\n",
      name, unit, s.rmse, s.mean, s.median, s.std, s.min, s.max);
}

void writeJson(const std::string& path, const nlohmann::json& j) {
  std::ofstream f(path);
  if (!f) rasm::throwInputError("--json " + path, "cannot open for writing");
  f << j.dump(2) << "\n";
  if (!f) rasm::throwInputError("--json " + path, "write failed");
  std::cout << "wrote " << path << "\n";
}

int eval(const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << kUsage;
    return args.empty() ? 1 : 0;
  }
  std::vector<std::string> pos;
  rasm::io::AteOptions ate;
  rasm::io::RpeOptions rpe;
  std::string json;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) rasm::throwInputError(a, "needs a value\n" + std::string(kUsage));
      return args[++i];
    };
    if (a == "--no-align")
      ate.align = false;
    else if (a == "--scale")
      ate.scale = true;
    else if (a == "--max-dt")
      ate.max_dt_s = parseNumber(a, value());
    else if (a == "--offset")
      ate.offset_s = rpe.offset_s = parseNumber(a, value());
    else if (a == "--delta")
      rpe.delta = parseNumber(a, value());
    else if (a == "--frames")
      rpe.delta_in_frames = true;
    else if (a == "--json")
      json = value();
    else if (a.rfind("--", 0) == 0)
      throw rasm::InputError("unknown option '" + a + "'\n" + std::string(kUsage));
    else
      pos.push_back(a);
  }
  if (pos.size() != 3)
    throw rasm::InputError("expected ate|rpe <groundtruth> <estimate>\n" + std::string(kUsage));
  if (!ate.align && ate.scale) throw rasm::InputError("--scale needs alignment (drop --no-align)");
  const auto gt = rasm::io::readTumTrajectory(pos[1]);
  const auto est = rasm::io::readTumTrajectory(pos[2]);

  if (pos[0] == "ate") {
    const auto r = rasm::io::TrajectoryEvaluator::computeAte(gt, est, ate);
    std::printf(
        "ATE  %s  %zu pose pairs (|dt| < %.3f s)  ground truth %zu poses, estimate %zu poses\n",
        !ate.align  ? "no alignment"
        : ate.scale ? "Sim(3) alignment"
                    : "SE(3) alignment",
        r.translation_m.count, ate.max_dt_s, gt.size(), est.size());
    printStats("translation", "[m]", r.translation_m);
    if (ate.scale) std::printf("  scale %.6f\n", r.scale);
    if (!json.empty()) writeJson(json, rasm::io::toJson(r, ate));
  } else if (pos[0] == "rpe") {
    const auto r = rasm::io::TrajectoryEvaluator::computeRpe(gt, est, rpe);
    std::printf("RPE  delta %g %s  %zu pose pairs\n", rpe.delta,
                rpe.delta_in_frames ? "frames" : "s", r.pairs);
    printStats("translation", "[m]", r.translation_m);
    printStats("rotation", "[deg]", r.rotation_deg);
    if (!json.empty()) writeJson(json, rasm::io::toJson(r, rpe));
  } else {
    throw rasm::InputError("unknown metric '" + pos[0] + "' (expected ate or rpe)\n" + kUsage);
  }
  return 0;
}

const rasm::app::Registrar reg{
    "eval", "trajectory metrics: ate | rpe <groundtruth.txt> <estimate.txt>", &eval};

}  // namespace
