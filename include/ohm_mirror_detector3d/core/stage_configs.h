// Each stage's own values, taken from the pipeline's parameters. This is the one place where
// core::Params meets the stages: the stages know only their configs (as KISS-ICP's modules
// do), and a value that is derived rather than given (a default that follows the sweep's
// sampling) is resolved here, once, into the configs the stages are built with.
#pragma once

#include "ohm_mirror_detector3d/core/cone_labelling.h"
#include "ohm_mirror_detector3d/core/echo_comparison.h"
#include "ohm_mirror_detector3d/core/object_extraction.h"
#include "ohm_mirror_detector3d/core/object_type.h"
#include "ohm_mirror_detector3d/core/outlier_filter.h"
#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/range_gate.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct StageConfigs
{
  RangeGateConfig range_gate;
  OutlierFilterConfig outlier_filter;
  EchoComparisonConfig echo_comparison;
  ObjectExtractionConfig object_extraction;
  ObjectTypeConfig object_type;
  ConeLabellingConfig cone_labelling;
};

StageConfigs stageConfigs(const Params& params);

}  // namespace core
}  // namespace ohm_mirror_detector3d
