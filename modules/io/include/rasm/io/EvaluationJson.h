#pragma once
// JSON form of the evaluation results (rasm eval, report.json).

#include <nlohmann/json.hpp>

#include "rasm/io/TrajectoryEvaluator.h"

namespace rasm::io {

nlohmann::json toJson(const ErrorStats& s);
nlohmann::json toJson(const AteResult& r, const AteOptions& opt);
nlohmann::json toJson(const RpeResult& r, const RpeOptions& opt);
nlohmann::json toJson(const WorldFrameError& r, const WorldFrameOptions& opt);

}  // namespace rasm::io
