#include "rasm/pipeline/Mapper.h"

#include <thread>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <chrono>
#include <mutex>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/Timing.h"
#include "rasm/pipeline/stages/ClassificationStage.h"
#include "rasm/pipeline/stages/ExplorationStage.h"
#include "rasm/pipeline/stages/FusionStages.h"
#include "rasm/pipeline/stages/PreprocessStage.h"
#include "rasm/pipeline/stages/SegmentationStage.h"
#include "rasm/pipeline/stages/TrackingStage.h"

namespace rasm::pipeline {

const char* toString(PoseSource s) {
  switch (s) {
    case PoseSource::Tracked:
      return "tracked";
    case PoseSource::Odometry:
      return "odometry";
    case PoseSource::MotionModel:
      return "motion_model";
    case PoseSource::Relocalised:
      return "relocalised";
  }
  return "?";
}

void Mapper::assemble() {
  m_stages.push_back(std::make_unique<PreprocessStage>());
  auto tracking = std::make_unique<TrackingStage>();
  m_tracking = tracking.get();
  m_stages.push_back(std::move(tracking));
  // Stages share engines and published layers, never each other.
  auto fusion_engine = std::make_shared<fusion::SurfelFusion>();
  m_stages.push_back(std::make_unique<IndexMapStage>(fusion_engine));
  m_stages.push_back(std::make_unique<SegmentationStage>(m_segments));
  m_stages.push_back(std::make_unique<FusionStage>(fusion_engine));
  m_stages.push_back(std::make_unique<ClassificationStage>(&m_segments));
  m_stages.push_back(std::make_unique<ExplorationStage>());
  indexTimers();
}

void Mapper::indexTimers() {
  m_timers.clear();
  for (const auto& s : m_stages) {
    s->m_timer = int(m_timers.size());
    m_timers.push_back(s->name());
    m_timers.insert(m_timers.end(), s->parts().begin(), s->parts().end());
  }
  m_lock_timer = int(m_timers.size());
  m_timers.push_back("map_lock_wait");
  m_timers.push_back("total");
}

std::vector<std::string> Mapper::stageTimerNames() const {
  std::vector<std::string> names;
  for (const auto& s : m_stages) names.push_back(s->name());
  return names;
}

void Mapper::addStage(std::unique_ptr<MapperStage> stage, const std::string& before) {
  if (m_frames > 0) throw std::logic_error("Mapper::addStage: before the first frame");
  auto at = m_stages.end();
  if (!before.empty()) {
    at = std::find_if(m_stages.begin(), m_stages.end(),
                      [&](const auto& s) { return s->name() == before; });
    if (at == m_stages.end()) throw std::logic_error("Mapper::addStage: no stage '" + before + "'");
  }
  stage->configure(m_mapper);
  m_stages.insert(at, std::move(stage));
  indexTimers();
}

Mapper::Mapper() {
  assemble();
  configure();
}

Mapper::Mapper(const mrpt::config::CConfigFileBase& ini, const std::string& source) {
  assemble();
  for (const ParamsSection& s : sections()) loadParamsStrict(ini, s.name, *s.params, source);
  configure();
}

Mapper::~Mapper() = default;

void Mapper::configure() {
  m_compute.apply();  // process-wide (ComputeOptions.h)
  for (const auto& s : m_stages) s->configure(m_mapper);
  m_map = std::make_unique<maps::CSurfelMap>(m_map_options);
}

std::vector<ParamsSection> Mapper::sections() {
  std::vector<ParamsSection> out = {
      {"mapper", &m_mapper}, {"map", &m_map_options}, {"compute", &m_compute}};
  for (const auto& s : m_stages)
    for (const ParamsSection& p : s->sections()) out.push_back(p);
  return out;
}

std::vector<std::string> Mapper::sectionNames() const {
  std::vector<std::string> names;
  for (const ParamsSection& s : const_cast<Mapper*>(this)->sections()) names.push_back(s.name);
  return names;
}

void Mapper::saveParams(mrpt::config::CConfigFileBase& out) const {
  for (const ParamsSection& s : const_cast<Mapper*>(this)->sections())
    s.params->saveToConfigFile(out, s.name);
}

FrameResult Mapper::processFrame(const RgbdFrame& frame) {
  const auto t_start = Clock::now();
  m_mapping_thread = std::this_thread::get_id();
  if (m_frames == 0) m_t0 = frame.timestamp_s;
  FrameContext& ctx = m_ctx;
  ctx.frame = &frame;
  ctx.t_rel_s = frame.timestamp_s - m_t0;
  ctx.index_map = {};
  ctx.labels.resize(0, 0);
  ctx.result = FrameResult();
  ctx.result.index = frame.index;
  ctx.result.timestamp_s = frame.timestamp_s;
  ctx.result.ms.assign(m_timers.size(), 0.0);
  std::unique_lock<std::shared_mutex> writing(m_map_mutex, std::defer_lock);
  const auto lockForWriting = [&] {
    if (writing.owns_lock()) return;
    const auto t = Clock::now();
    writing.lock();
    ctx.result.ms[std::size_t(m_lock_timer)] = msSince(t);
  };
  for (const auto& s : m_stages) {
    if (s->writesMap()) lockForWriting();
    const auto t = Clock::now();
    s->process(ctx, *m_map);
    ctx.result.ms[s->m_timer] += msSince(t);
  }
  lockForWriting();
  for (const auto& s : m_stages) s->finishFrame(ctx, *m_map);
  if (!ctx.result.tracked) ++m_lost;
  ++m_frames;
  writing.unlock();
  {
    std::lock_guard<std::mutex> lk(m_phase_mutex);
    ++m_write_phases;
  }
  m_phase_cv.notify_all();
  ctx.result.ms.back() = msSince(t_start);
  ctx.frame = nullptr;  // the caller's frame is not kept
  return ctx.result;
}

std::string Mapper::csvHeader() const {
  std::string h = "index,timestamp_s,tracked";
  std::vector<std::string> cols;
  for (const auto& s : m_stages) s->csvColumns(cols);
  for (const auto& c : cols) h += "," + c;
  for (const auto& t : m_timers) h += ",ms_" + t;
  return h;
}

std::string Mapper::csvRow() const {
  CsvRow row;
  const FrameResult& r = m_ctx.result;
  row.add(r.index).add(r.timestamp_s, 6).add(r.tracked);
  for (const auto& s : m_stages) s->csvValues(m_ctx, row);
  for (double ms : r.ms) row.add(ms, 2);
  return row.text();
}

void Mapper::report(nlohmann::json& rep) const {
  for (const auto& s : m_stages) s->report(rep);
  rep["keyframes"] = m_map->keyframes().size();
}

void Mapper::finishRun() {
  std::unique_lock<std::shared_mutex> writing(m_map_mutex);
  for (const auto& s : m_stages) s->finishRun(*m_map);
}

void Mapper::writeOutputs(OutputFolder& out) {
  std::unique_lock<std::shared_mutex> writing(m_map_mutex);  // stages may refresh their tables
  for (const auto& s : m_stages) s->writeOutputs(out, *m_map);
}

std::size_t Mapper::relocalisations() const {
  return m_tracking->relocalisations();
}
const Eigen::Isometry3d& Mapper::pose() const {
  return m_tracking->tracker().lastGoodPose();
}
const Eigen::Isometry3d& Mapper::lastFramePose() const {
  return m_tracking->lastFramePose();
}

std::shared_ptr<const MapSnapshot> Mapper::snapshot() const {
  auto snap = std::make_shared<MapSnapshot>();
  snapshotInto(*snap);
  return snap;
}

void Mapper::snapshotInto(MapSnapshot& snap) const {
  copySnapshot(snap, 0);
  const auto t = Clock::now();
  snap.store.rebuildIndex();
  snap.index_ms = msSince(t);
}

void Mapper::snapshotThinnedInto(MapSnapshot& snap, int max_surfels) const {
  copySnapshot(snap, std::max(1, max_surfels));
  snap.index_ms = 0.0;
}

void Mapper::copySnapshot(MapSnapshot& snap, int max_surfels) const {
  // From the mapping thread itself (between frames) nothing writes: copy at once.
  if (std::this_thread::get_id() != m_mapping_thread.load()) {
    std::unique_lock<std::mutex> lk(m_phase_mutex);
    const std::uint64_t seen = m_write_phases;
    m_phase_cv.wait_for(lk, std::chrono::milliseconds(200), [&] { return m_write_phases != seen; });
  }
  {
    std::shared_lock<std::shared_mutex> reading(m_map_mutex);
    const auto t = Clock::now();
    const maps::SurfelStore& live = m_map->store();
    if (max_surfels > 0 && live.size() > max_surfels)
      snap.store.copyThinnedFrom(live, (live.size() + max_surfels - 1) / max_surfels, 1.0f);
    else
      snap.store.copySurfelsFrom(live);
    snap.segments = m_segments.table().segments();
    snap.relabel_generation = m_segments.relabelGeneration();
    snap.frames = m_frames;
    snap.copy_ms = msSince(t);
  }
}

void Mapper::loadMap(const std::string& path) {
  if (m_frames > 0) throwInputError("map '" + path + "'", "must be loaded before the first frame");
  auto loaded = std::make_unique<maps::CSurfelMap>(m_map_options);
  try {
    mrpt::io::CFileGZInputStream f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    a >> *loaded;
  } catch (const std::exception& e) {
    throwInputError("map '" + path + "'",
                    std::string("cannot be read as a rasm surfel map (.surfelmap): ") + e.what());
  }
  if (loaded->keyframes().empty())
    throwInputError("map '" + path + "'",
                    "has no relocalisation keyframes: the camera cannot be localised in it");
  std::unique_lock<std::shared_mutex> writing(m_map_mutex);
  m_map = std::move(loaded);
  m_tracking->localiseInLoadedMap();
}

void Mapper::renderView(const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K,
                        maps::RenderedMaps& out) {
  maps::RenderOptions ro;
  ro.max_depth_m = 20.0f;
  m_renderer.render(m_map->store(), T_world_cam, K, ro, out);
}

}  // namespace rasm::pipeline
