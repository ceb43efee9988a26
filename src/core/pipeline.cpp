#include "ohm_mirror_detector3d/core/pipeline.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "ohm_mirror_detector3d/core/echo_comparison.h"
#include "ohm_mirror_detector3d/core/range_gate.h"

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
void throwIfInvalid(const Params& params)
{
  const std::vector<std::string> errors = params.validate();
  if (errors.empty())
    return;
  std::string message = "invalid pre-filter parameters:";
  for (const std::string& error : errors)
    message += "\n  " + error;
  throw std::invalid_argument(message);
}
}  // namespace

Pipeline::Pipeline(const Params& params)
{
  setParams(params);
}

void Pipeline::setParams(const Params& params)
{
  throwIfInvalid(params);
  params_ = params;
}

const PipelineResult& Pipeline::process(const Sweep& sweep)
{
  SweepLabels& labels = result_.labels;
  labels.reset(sweep.beamCount());
  result_.range_gated_points = applyRangeGate(sweep, params_, labels);
  result_.error_surface_points = compareEchoes(sweep, params_, labels);
  // Whatever no stage claimed is unaffected by any surface.
  for (std::vector<Label>& echo_labels : labels.echoes)
    std::replace(echo_labels.begin(), echo_labels.end(), Label::unchecked, Label::valid);
  collectCleaned(sweep, labels, result_.cleaned);
  return result_;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
