#pragma once
// The versions of a run folder's two tables (docs/outputs.md): report.json "report_schema" and
// "frames_schema", written by the run and checked by the readers of report.json and frames.csv.

namespace rasm::pipeline {

/// report.json "report_schema" and "frames_schema": raised when a field or column is renamed,
/// removed or changes its meaning or unit (new fields and columns keep the version: read columns
/// by name).
constexpr int kReportSchema = 1;
constexpr int kFramesSchema = 1;

}  // namespace rasm::pipeline
