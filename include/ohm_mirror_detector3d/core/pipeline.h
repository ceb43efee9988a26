// The pre-filter of one sweep (Algorithm 1 of the paper): composes the stages and owns
// their buffers, which it reuses from sweep to sweep.
#pragma once

#include <cstddef>
#include <vector>

#include "ohm_mirror_detector3d/core/cleaned_output.h"
#include "ohm_mirror_detector3d/core/cone_labelling.h"
#include "ohm_mirror_detector3d/core/object_extraction.h"
#include "ohm_mirror_detector3d/core/object_type.h"
#include "ohm_mirror_detector3d/core/outlier_filter.h"
#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// Wall time of each stage of the last Pipeline::process (steady_clock, seconds). Stages that
// did not run (no object candidates) stay 0. For profiling; costs a few clock reads per sweep.
struct StageTimes
{
  double range_gate = 0.0;
  double outlier_filter = 0.0;      // both passes
  double echo_comparison = 0.0;
  double object_extraction = 0.0;
  double type_analysis = 0.0;
  double cone_labelling = 0.0;
  double cleaned_output = 0.0;
  double total = 0.0;               // the whole process call

  double sumOfStages() const
  {
    return range_gate + outlier_filter + echo_comparison + object_extraction + type_analysis + cone_labelling +
           cleaned_output;
  }
};

struct PipelineResult
{
  SweepLabels labels;
  ObjectAssignment assignment;             // object of each surface/behind point
  std::vector<ReflectiveObject> objects;
  std::vector<OutputPoint> cleaned;
  std::size_t range_gated_points = 0;      // labelled nanPoint by the range gate
  std::size_t outlier_points = 0;          // labelled nanPoint by both outlier filter passes
  std::size_t error_surface_points = 0;    // n_affected of the echo comparison
  StageTimes times;                        // per-stage wall time of this sweep
};

class Pipeline
{
public:
  // Throws std::invalid_argument naming every bad value when params.validate() fails.
  explicit Pipeline(const Params& params = Params());

  // Same check as the constructor; on failure the previous parameters stay in force.
  void setParams(const Params& params);
  const Params& params() const { return params_; }

  // Runs every stage on the sweep. The result is valid until the next call.
  const PipelineResult& process(const Sweep& sweep);

private:
  Params params_;
  OutlierFilter outlier_filter_;
  ObjectExtractor object_extractor_;
  ObjectTypeAnalyzer type_analyzer_;
  PipelineResult result_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
