#pragma once
// The documentation of a run folder (`rasm help outputs`, docs/outputs.md): every file, every
// report.json field, every frames.csv column, the JSON files of the stages and the PLY layout.
// The frames.csv part is derived from the assembled Mapper's stage list (each stage's columns and
// timers), so a stage's new column shows up at once; its meaning comes from the table in
// OutputsDoc.cpp, and tests/app/OutputsDoc_unittest.cpp checks that every column and report field
// of a real run is described there.

#include <string>
#include <vector>

#include "rasm/pipeline/OutputSchema.h"

namespace rasm::pipeline {
class Mapper;
}  // namespace rasm::pipeline

namespace rasm::run {

using pipeline::kFramesSchema;
using pipeline::kReportSchema;

/// The columns MappingRun appends to each frames.csv row after the Mapper's (memory now; the
/// objects correct against a simulated world's truth where measured at this frame).
inline const std::vector<std::string>& runCsvColumns() {
  static const std::vector<std::string> c = {"rss_mb", "map_memory_bytes", "objects_correct",
                                             "objects_detectable"};
  return c;
}

/// One frames.csv column: who writes it (a stage's name, "mapper" or "run") and what it holds
/// (empty: not documented in OutputsDoc.cpp).
struct CsvColumnDoc {
  std::string name, writer, meaning;
};

/// Every frames.csv column of a run of `mapper`, in file order.
std::vector<CsvColumnDoc> framesCsvColumns(const pipeline::Mapper& mapper);

/// The whole documentation as Markdown (docs/outputs.md is this text).
std::string outputsDocumentation(const pipeline::Mapper& mapper);

}  // namespace rasm::run
