#include "ohm_mirror_detector3d/core/pipeline.h"

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
  PipelineResult& r = result_;
  r.labels.reset(sweep.beamCount());
  r.objects.clear();
  r.range_gated_points = applyRangeGate(sweep, params_, r.labels);
  r.outlier_points = outlier_filter_.apply(sweep, params_, Label::unchecked, r.labels);
  r.error_surface_points = compareEchoes(sweep, params_, r.labels);
  if (r.error_surface_points >= static_cast<std::size_t>(params_.min_object_points))
  {
    r.outlier_points += outlier_filter_.apply(sweep, params_, Label::errorSurface, r.labels);
    object_extractor_.extract(sweep, params_, r.labels, r.objects);
    for (ReflectiveObject& object : r.objects)
      type_analyzer_.analyze(sweep, params_, r.labels, object);
  }
  labelByVisionCones(sweep, params_, r.objects, r.labels, r.assignment);
  collectCleaned(sweep, r.labels, r.objects, r.assignment, r.cleaned);
  return r;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
