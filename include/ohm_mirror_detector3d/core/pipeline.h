// The pre-filter of one sweep (Algorithm 1 of the paper) in three phases:
//   detect: the sweep's sampling, range gate, outlier filter, echo comparison, object
//     extraction, mixed pixels, the per-point evidence (reflection_evidence.h), type decision
//     (the objects and why);
//   object stages: an ordered list of optional stages on whole objects (object_stage.h): first
//     those the parameters switch on (phantom_plane_share: phantom_planes.h; grow_objects:
//     glass_growth.h, and mirror_growth.h with 1; shared_normal_angle: shared_normals.h;
//     post_filter: post_filter.h), built here from Params for every front end alike, then any
//     added with addObjectStage;
//   label: cone labelling, reflection chains (where each phantom really is, reflection_chains.h),
//     cleaned output with back-projection.
// The stages are built from Params (stage_configs.h), each with only its own values; the
// pipeline owns their buffers and reuses them from sweep to sweep.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "ohm_mirror_detector3d/core/cleaned_output.h"
#include "ohm_mirror_detector3d/core/cone_labelling.h"
#include "ohm_mirror_detector3d/core/echo_comparison.h"
#include "ohm_mirror_detector3d/core/mixed_pixels.h"
#include "ohm_mirror_detector3d/core/object_extraction.h"
#include "ohm_mirror_detector3d/core/object_map.h"
#include "ohm_mirror_detector3d/core/object_stage.h"
#include "ohm_mirror_detector3d/core/object_type.h"
#include "ohm_mirror_detector3d/core/outlier_filter.h"
#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/range_gate.h"
#include "ohm_mirror_detector3d/core/reflection_chains.h"
#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/removal_report.h"
#include "ohm_mirror_detector3d/core/stage_configs.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_context.h"
#include "ohm_mirror_detector3d/core/sweep_sampling.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// Wall time of each stage of the last Pipeline::process (steady_clock, seconds). Stages that
// did not run (no object candidates) stay 0. For profiling; costs a few clock reads per sweep.
struct StageTimes
{
  double sampling = 0.0;            // working out the sweep's sampling
  double range_gate = 0.0;
  double outlier_filter = 0.0;      // both passes
  double echo_comparison = 0.0;
  double object_extraction = 0.0;  // mixed pixels included
  double type_analysis = 0.0;
  double object_stages = 0.0;       // all of them
  double cone_labelling = 0.0;
  double reflection_chains = 0.0;
  double cleaned_output = 0.0;
  double total = 0.0;               // the whole process call

  double sumOfStages() const
  {
    return sampling + range_gate + outlier_filter + echo_comparison + object_extraction + type_analysis +
           object_stages + cone_labelling + reflection_chains + cleaned_output;
  }
};

struct PipelineResult
{
  SweepLabels labels;
  ObjectAssignment assignment;             // object of each surface/behind point
  ReflectionPaths paths;                   // the chain of mirrors of each phantom (behindReflective)
  ReflectionChainCounts reflection_chains; // phantoms reflected more than once, and those none explains
  std::vector<ReflectiveObject> objects;
  std::vector<OutputPoint> cleaned;
  SweepSampling sampling;                  // the sweep's grid and angular steps, as worked out
  std::size_t range_gated_points = 0;      // labelled nanPoint by the range gate
  std::size_t outlier_points = 0;          // labelled nanPoint by both outlier filter passes
  std::size_t error_surface_points = 0;    // n_affected of the echo comparison, plus the specular spots' returns
  std::size_t specular_spot_points = 0;    // returns of specular spots (specular_spots.h) labelled errorSurface
  // Beams whose errorSurface echo the outlier filter's errorSurface pass in the sweep's
  // sampling found without support (both echoes unchecked again), and mixed pixels (MixedPixels).
  std::size_t released_surface_beams = 0;
  std::size_t mixed_pixel_beams = 0;
  // The smallest distance between a beam's two echoes the sensor resolved in this sweep
  // (ReflectionEvidence::echoSeparation) [m]; NaN when the per-point evidence was not built (no
  // object with points behind it), 0 with too few double echoes to tell.
  float echo_separation = 0.0f;
  RemovalCounts removals;                  // for implausibleRemovals (removal_report.h)
  StageTimes times;                        // per-stage wall time of this sweep
};

class Pipeline
{
public:
  // Throws std::invalid_argument naming every bad value when params.validate() fails.
  explicit Pipeline(const Params& params = Params());

  // Same check as the constructor; on success the stages are rebuilt from the new values (the
  // object stages the parameters switch on too), on failure the previous parameters and stages
  // stay in force. Object stages added with addObjectStage are kept.
  void setParams(const Params& params);
  const Params& params() const { return params_; }

  // The post-filter's object map (post_filter = 1): kept over sweeps and over setParams (a new
  // cell size clears it: its cells would not fit); loaded into and saved from here.
  ObjectMap& objectMap() { return object_map_; }
  const ObjectMap& objectMap() const { return object_map_; }

  // Appends a stage to the object stages; they run in the order added, after those the
  // parameters switch on.
  void addObjectStage(std::unique_ptr<ObjectStage> stage);

  // Runs the three phases on the sweep; the sensor origin (the apex of the vision cones)
  // is context.sensorOrigin(), the origin the sweep's ranges were computed from
  // (Sweep::computeRanges). The sweep's sampling is worked out from the sweep itself first
  // (SamplingEstimator): the stages whose parameters are automatic follow it. The result is
  // valid until the next call.
  const PipelineResult& process(const Sweep& sweep, const SweepContext& context);

private:
  struct Stages
  {
    explicit Stages(const StageConfigs& configs);

    RangeGate range_gate;
    OutlierFilter outlier_filter;
    EchoComparison echo_comparison;
    SpecularSpots specular_spots;
    ObjectExtractor object_extractor;
    MixedPixels mixed_pixels;
    ObjectTypeAnalyzer type_analyzer;
    ConeLabelling cone_labelling;
    ReflectionChains reflection_chains;
    // The object extraction's n_object: with fewer errorSurface points detect skips the
    // errorSurface pass and object extraction, since they cannot make an object (mixed pixels
    // are still looked for among them).
    std::size_t min_object_points;
  };

  // Times consecutive stages (pipeline.cpp).
  class StageClock;
  void detect(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, StageClock& clock);
  void runObjectStages(const Sweep& sweep, const SweepContext& context, StageClock& clock);
  void label(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, StageClock& clock);

  Params params_;
  StageConfigs configs_;
  Stages stages_;
  // The per-point evidence of the current sweep: built once per sweep, when the first stage
  // needs it (an object found, or object stages to run).
  const ReflectionEvidence& evidence(const Sweep& sweep, const Eigen::Vector3f& sensor_origin);
  ReflectionEvidence evidence_;
  bool evidence_built_ = false;
  SamplingEstimator sampling_estimator_;
  std::vector<std::uint8_t> in_range_;  // per beam, for RemovalCounts (pipeline.cpp)
  ObjectMap object_map_;
  // The object stages the parameters switch on (parameterStages in pipeline.cpp), then the added ones.
  std::vector<std::unique_ptr<ObjectStage>> parameter_stages_;
  std::vector<std::unique_ptr<ObjectStage>> object_stages_;
  PipelineResult result_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
