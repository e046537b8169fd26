#pragma once
// The seam every stage of the Mapper plugs into (DESIGN.md "Stages, threads and the map they
// share"). A stage owns its INI sections, its timers and its frames.csv / report.json fields; the
// Mapper runs the stages in order over one FrameContext per frame and derives the known sections,
// config.ini, the timing table and the CSV columns from the list. Adding a stage is one class
// deriving from MapperStage plus one line in Mapper::assemble().
//
//   class MyStage : public MapperStage {
//    public:
//     MyStage() : MapperStage("my_stage") {}
//     std::vector<ParamsSection> sections() override { return {{"my_stage", &m_params}}; }
//     void process(FrameContext& ctx, maps::CSurfelMap& map) override { ... }
//     void csvColumns(std::vector<std::string>& c) const override { c.push_back("my_count"); }
//     void csvValues(const FrameContext&, CsvRow& row) const override { row.add(m_count); }
//   };

#include <mrpt/config/CLoadableOptions.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rasm/pipeline/FrameContext.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/pipeline/RunParams.h"
#include "rasm/surfel_map/CSurfelMap.h"

namespace rasm::pipeline {

/// One INI section and the params struct that loads it.
struct ParamsSection {
  std::string name;
  mrpt::config::CLoadableOptions* params = nullptr;
};

/// One frames.csv row under construction (comma-separated, fixed precision per call).
class CsvRow {
 public:
  CsvRow& add(long long v);
  CsvRow& add(int v) { return add(static_cast<long long>(v)); }
  CsvRow& add(std::size_t v) { return add(static_cast<long long>(v)); }
  CsvRow& add(bool v) { return add(static_cast<long long>(v)); }
  CsvRow& add(double v, int decimals);
  CsvRow& add(const std::string& v);  ///< commas and line breaks are replaced by ';' and ' '
  CsvRow& add(const char* v) { return add(std::string(v)); }
  const std::string& text() const { return m_text; }

 private:
  void separate();
  std::string m_text;
  bool m_first = true;
};

class MapperStage {
 public:
  /// `name`: the stage's timer (report.json "stages", frames.csv ms_<name>); `parts`: timers of
  /// parts of it the stage records itself (recordMs).
  explicit MapperStage(std::string name, std::vector<std::string> parts = {})
      : m_name(std::move(name)), m_parts(std::move(parts)) {}
  virtual ~MapperStage() = default;
  MapperStage(const MapperStage&) = delete;
  MapperStage& operator=(const MapperStage&) = delete;

  const std::string& name() const { return m_name; }
  const std::vector<std::string>& parts() const { return m_parts; }

  /// The INI sections this stage owns (loaded strictly before configure()).
  virtual std::vector<ParamsSection> sections() { return {}; }
  /// Called once the sections are loaded and after any later change of them: validate across
  /// sections, size internals. `mapper` holds the Mapper's own [mapper] params.
  virtual void configure(const TMapperParams& /*mapper*/) {}
  /// Whether process() changes the map. The Mapper holds its map lock exclusively from the first
  /// such stage to the end of the frame (every finishFrame() runs under it), so other threads
  /// can copy the map (Mapper::snapshot) while the stages before it only read.
  virtual bool writesMap() const { return false; }
  /// The stage's work on one frame.
  virtual void process(FrameContext& ctx, maps::CSurfelMap& map) = 0;
  /// After every stage processed the frame (e.g. keyframes of fused frames).
  virtual void finishFrame(FrameContext& /*ctx*/, maps::CSurfelMap& /*map*/) {}
  /// After the last frame, before any output is written (Mapper::finishRun): work still in
  /// flight (e.g. detections) lands in the map.
  virtual void finishRun(maps::CSurfelMap& /*map*/) {}

  /// frames.csv: column names, and the values of one frame in the same order.
  virtual void csvColumns(std::vector<std::string>& /*columns*/) const {}
  virtual void csvValues(const FrameContext& /*ctx*/, CsvRow& /*row*/) const {}
  /// report.json: fields of the whole run (counts, rates); called once at the end.
  virtual void report(nlohmann::json& /*rep*/) const {}
  /// The stage's own files in the run's output folder (e.g. segments.json), at the end of a run
  /// and after report(); written through the folder (OutputFiles.h: atomically, and recorded for
  /// report.json and for clearing by the next run; a new file name goes into knownNames()).
  virtual void writeOutputs(OutputFolder& /*out*/, const maps::CSurfelMap& /*map*/) {}

 protected:
  /// Records part `part` (index into parts()) of this frame's time.
  void recordMs(FrameContext& ctx, int part, double ms) const {
    ctx.result.ms[m_timer + 1 + part] += ms;
  }

 private:
  friend class Mapper;
  std::string m_name;
  std::vector<std::string> m_parts;
  int m_timer = 0;  ///< index of this stage's timer in FrameResult::ms (set by the Mapper)
};

}  // namespace rasm::pipeline
