#pragma once
// II-A: the frame's depth, bilateral-filtered (KinectFusion), into a pyramid of vertex and normal
// maps in the camera frame (FrameContext::pyramid). Its params are the Mapper's [mapper] section
// (the depth range and pyramid depth every later stage shares).

#include "rasm/pipeline/MapperStage.h"

namespace rasm::pipeline {

class PreprocessStage : public MapperStage {
 public:
  PreprocessStage() : MapperStage("preprocess") {}
  void configure(const TMapperParams& mapper) override { m_params = mapper; }
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;

 private:
  TMapperParams m_params;
  Image<float> m_depth_filtered;
};

}  // namespace rasm::pipeline
