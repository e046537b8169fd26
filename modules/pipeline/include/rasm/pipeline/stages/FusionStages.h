#pragma once
// II-B, II-D as two stages around the ones that need the map's view of the frame (label
// propagation, III):
//   IndexMapStage  renders fusion's 4x point index map at T_t (FrameContext::index_map);
//   FusionStage    associates and updates (with L^p when a stage wrote FrameContext::labels),
//                  adds new surfels, then cleans up (carve, prune, merge). Section [fusion].
// Both act only on frames that may be fused (FrameResult::fusable) and share one SurfelFusion,
// which FusionStage owns.

#include "rasm/fusion/SurfelFusion.h"
#include "rasm/pipeline/MapperStage.h"

namespace rasm::pipeline {

class FusionStage : public MapperStage {
 public:
  FusionStage() : MapperStage("fuse") {}
  std::vector<ParamsSection> sections() override { return {{"fusion", &m_params}}; }
  void configure(const TMapperParams& mapper) override;
  bool writesMap() const override { return true; }
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;
  void csvColumns(std::vector<std::string>& columns) const override;
  void csvValues(const FrameContext& ctx, CsvRow& row) const override;

  const fusion::TFusionParams& params() const { return m_params; }
  fusion::SurfelFusion& fusion() { return m_fusion; }

 private:
  fusion::TFusionParams m_params;
  fusion::SurfelFusion m_fusion;
};

class IndexMapStage : public MapperStage {
 public:
  explicit IndexMapStage(FusionStage& fusion) : MapperStage("index_map"), m_fusion(fusion) {}
  bool writesMap() const override { return true; }  ///< the render may re-sort the store
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;

 private:
  FusionStage& m_fusion;
};

}  // namespace rasm::pipeline
