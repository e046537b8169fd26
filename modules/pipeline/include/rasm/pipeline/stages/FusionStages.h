#pragma once
// II-B, II-D as two stages around the ones that need the map's view of the frame (label
// propagation, III):
//   IndexMapStage  renders fusion's 4x point index map at T_t (FrameContext::index_map);
//   FusionStage    associates and updates (with L^p when a stage wrote FrameContext::labels),
//                  adds new surfels, then cleans up (carve, prune, merge). Section [fusion].
// Both act only on frames that may be fused (FrameResult::fusable). They are two phases of one
// SurfelFusion engine (its index map is what the update associates against), which the Mapper
// creates and hands to both; FusionStage configures it from [fusion].

#include <memory>

#include "rasm/fusion/SurfelFusion.h"
#include "rasm/pipeline/MapperStage.h"

namespace rasm::pipeline {

class FusionStage : public MapperStage {
 public:
  explicit FusionStage(std::shared_ptr<fusion::SurfelFusion> engine)
      : MapperStage("fuse"), m_fusion(std::move(engine)) {}
  std::vector<ParamsSection> sections() override { return {{"fusion", &m_params}}; }
  void configure(const TMapperParams& mapper) override;
  bool writesMap() const override { return true; }
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;
  void csvColumns(std::vector<std::string>& columns) const override;
  void csvValues(const FrameContext& ctx, CsvRow& row) const override;

  const fusion::TFusionParams& params() const { return m_params; }
  fusion::SurfelFusion& fusion() { return *m_fusion; }

 private:
  fusion::TFusionParams m_params;
  std::shared_ptr<fusion::SurfelFusion> m_fusion;
};

class IndexMapStage : public MapperStage {
 public:
  explicit IndexMapStage(std::shared_ptr<fusion::SurfelFusion> engine)
      : MapperStage("index_map"), m_fusion(std::move(engine)) {}
  bool writesMap() const override { return true; }  ///< the render may re-sort the store
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;

 private:
  std::shared_ptr<fusion::SurfelFusion> m_fusion;
};

}  // namespace rasm::pipeline
