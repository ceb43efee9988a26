#include "ohm_mirror_detector3d/core/pipeline.h"

#include <chrono>
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
using Clock = std::chrono::steady_clock;

// Seconds since `start`; moves `start` to now, so consecutive calls time consecutive stages.
double lap(Clock::time_point& start)
{
  const Clock::time_point now = Clock::now();
  const double seconds = std::chrono::duration<double>(now - start).count();
  start = now;
  return seconds;
}

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
  r.times = StageTimes();
  const Clock::time_point begin = Clock::now();
  Clock::time_point t = begin;
  r.labels.reset(sweep.beamCount());
  r.objects.clear();
  r.range_gated_points = applyRangeGate(sweep, params_, r.labels);
  r.times.range_gate = lap(t);
  r.outlier_points = outlier_filter_.apply(sweep, params_, Label::unchecked, r.labels);
  r.times.outlier_filter = lap(t);
  r.error_surface_points = compareEchoes(sweep, params_, r.labels);
  r.times.echo_comparison = lap(t);
  if (r.error_surface_points >= static_cast<std::size_t>(params_.min_object_points))
  {
    r.outlier_points += outlier_filter_.apply(sweep, params_, Label::errorSurface, r.labels);
    r.times.outlier_filter += lap(t);
    object_extractor_.extract(sweep, params_, r.labels, r.objects);
    r.times.object_extraction = lap(t);
    if (!r.objects.empty())
      type_analyzer_.beginSweep(sweep);
    for (ReflectiveObject& object : r.objects)
      type_analyzer_.analyze(sweep, params_, r.labels, object);
    r.times.type_analysis = lap(t);
  }
  labelByVisionCones(sweep, params_, r.objects, r.labels, r.assignment);
  r.times.cone_labelling = lap(t);
  collectCleaned(sweep, r.labels, r.objects, r.assignment, r.cleaned);
  r.times.cleaned_output = lap(t);
  r.times.total = std::chrono::duration<double>(t - begin).count();
  return r;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
