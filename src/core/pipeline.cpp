#include "ohm_mirror_detector3d/core/pipeline.h"

#include "ohm_mirror_detector3d/core/glass_growth.h"
#include "ohm_mirror_detector3d/core/grown_pane_refinement.h"
#include "ohm_mirror_detector3d/core/shared_normals.h"
#include "ohm_mirror_detector3d/core/intensity_evidence.h"
#include "ohm_mirror_detector3d/core/mirror_growth.h"
#include "ohm_mirror_detector3d/core/phantom_planes.h"
#include "ohm_mirror_detector3d/core/post_filter.h"

#include <chrono>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
const Params& checked(const Params& params)
{
  const std::vector<std::string> errors = params.validate();
  if (errors.empty())
    return params;
  std::string message = "invalid pre-filter parameters:";
  for (const std::string& error : errors)
    message += "\n  " + error;
  throw std::invalid_argument(message);
}
// Bits of Pipeline::in_range_ per beam.
constexpr std::uint8_t kFirstInRange = 1;
constexpr std::uint8_t kSecondInRange = 2;  // a point of its own (not echo 1 repeated)
constexpr std::uint8_t kTwoReturns = 4;     // both, and they differ

// Counts the points the range gate left (a single return repeated in both echoes once) and
// marks them per beam, so that what the outlier filter removes of them can be counted after it.
void countInRange(const Sweep& sweep, const SweepLabels& labels, std::vector<std::uint8_t>& marks,
                  RemovalCounts& counts)
{
  const std::size_t beams = sweep.beamCount();
  marks.resize(beams);
  counts = RemovalCounts();
  for (std::size_t b = 0; b < beams; ++b)
  {
    const bool first = labels.echoes[0][b] != Label::nanPoint;
    const bool second = labels.echoes[1][b] != Label::nanPoint &&
                        !(first && sweep.echoes[1].points[b] == sweep.echoes[0].points[b]);
    marks[b] = static_cast<std::uint8_t>((first ? kFirstInRange : 0) | (second ? kSecondInRange : 0) |
                                         (first && second ? kTwoReturns : 0));
    counts.in_range_points += (first ? 1 : 0) + (second ? 1 : 0);
    counts.second_returns += first && second ? 1 : 0;
  }
}

void countRemoved(const std::vector<std::uint8_t>& marks, const SweepLabels& labels, RemovalCounts& counts)
{
  for (std::size_t b = 0; b < marks.size(); ++b)
  {
    const std::uint8_t m = marks[b];
    const bool first_removed = (m & kFirstInRange) && labels.echoes[0][b] == Label::nanPoint;
    const bool second_removed = (m & kSecondInRange) && labels.echoes[1][b] == Label::nanPoint;
    counts.outlier_removed += (first_removed ? 1 : 0) + (second_removed ? 1 : 0);
    counts.second_returns_removed += (m & kTwoReturns) && second_removed ? 1 : 0;
  }
}

// The object stages the parameters switch on, in the order they run: the one place where the
// nodelet, prefilter_bag and the Python API get them from.
// The post-filter comes last: it merges what the sweep grew.
std::vector<std::unique_ptr<ObjectStage>> parameterStages(const StageConfigs& configs, ObjectMap& object_map,
                                                          ObjectTypeAnalyzer& type_analyzer)
{
  std::vector<std::unique_ptr<ObjectStage>> stages;
  // First: an object made of another's phantoms is no surface, to grow or to type by intensity.
  if (configs.phantom_planes.enabled)
    stages.push_back(std::make_unique<PhantomPlanes>(configs.phantom_planes));
  // Before the growth stages, which grow mirrors and panes by their type.
  if (configs.intensity.enabled)
    stages.push_back(std::make_unique<IntensityEvidence>(configs.intensity, &type_analyzer));
  if (configs.growth.mirrors)
    stages.push_back(std::make_unique<MirrorGrowth>(configs.growth));
  if (configs.growth.panes)
  {
    stages.push_back(std::make_unique<GlassGrowth>(configs.growth));
    stages.push_back(std::make_unique<GrownPaneRefinement>(type_analyzer));
    // Once more after growth, for the panes it grew: before it, a pane is often a handful of patches
    // a few centimetres wide, none of which holds the phantom plane in front of which it stands.
    if (configs.phantom_planes.enabled)
    {
      PhantomPlaneConfig grown_panes = configs.phantom_planes;
      grown_panes.grown_hosts_only = true;
      stages.push_back(std::make_unique<PhantomPlanes>(grown_panes));
    }
  }
  // Last before the map: every plane as the sweep's own stages left it, the map fed the shared one.
  if (configs.shared_normals.enabled)
    stages.push_back(std::make_unique<SharedNormals>(configs.shared_normals));
  if (configs.object_map.enabled)
    stages.push_back(std::make_unique<PostFilter>(object_map));
  return stages;
}
}  // namespace

class Pipeline::StageClock
{
public:
  using Clock = std::chrono::steady_clock;

  StageClock() : begin_(Clock::now()), last_(begin_) {}

  // Seconds since the previous lap (or the start), so consecutive calls time consecutive stages.
  double lap()
  {
    const Clock::time_point now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }
  // From the start to the last lap.
  double total() const { return std::chrono::duration<double>(last_ - begin_).count(); }

private:
  Clock::time_point begin_;
  Clock::time_point last_;
};

Pipeline::Stages::Stages(const StageConfigs& configs)
  : range_gate(configs.range_gate)
  , outlier_filter(configs.outlier_filter)
  , echo_comparison(configs.echo_comparison)
  , specular_spots(configs.specular_spots)
  , object_extractor(configs.object_extraction)
  , mixed_pixels(configs.mixed_pixels)
  , type_analyzer(configs.object_type)
  , cone_labelling(configs.cone_labelling)
  , reflection_chains(configs.reflection_chains)
  , min_object_points(static_cast<std::size_t>(configs.object_extraction.min_object_points))
{
}

Pipeline::Pipeline(const Params& params)
  : params_(checked(params))
  , configs_(stageConfigs(params_))
  , stages_(configs_)
  , object_map_(configs_.object_map)
  , parameter_stages_(parameterStages(configs_, object_map_, stages_.type_analyzer))
{
}

void Pipeline::setParams(const Params& params)
{
  StageConfigs configs = stageConfigs(checked(params));
  Stages stages(configs);
  stages_ = std::move(stages);
  object_map_.setConfig(configs.object_map);
  parameter_stages_ = parameterStages(configs, object_map_, stages_.type_analyzer);
  configs_ = configs;
  params_ = params;
}

void Pipeline::addObjectStage(std::unique_ptr<ObjectStage> stage)
{
  object_stages_.push_back(std::move(stage));
}

const PipelineResult& Pipeline::process(const Sweep& sweep, const SweepContext& context)
{
  result_.times = StageTimes();
  evidence_built_ = false;
  StageClock clock;
  const Eigen::Vector3f sensor_origin = context.sensorOrigin();
  detect(sweep, sensor_origin, clock);
  runObjectStages(sweep, context, clock);
  label(sweep, sensor_origin, clock);
  result_.times.total = clock.total();
  return result_;
}

void Pipeline::detect(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, StageClock& clock)
{
  PipelineResult& r = result_;
  Stages& s = stages_;
  r.labels.reset(sweep.beamCount());
  r.objects.clear();
  r.released_surface_beams = 0;
  r.mixed_pixel_beams = 0;
  r.sampling = sampling_estimator_.estimate(sweep, sensor_origin);
  r.times.sampling = clock.lap();
  r.range_gated_points = s.range_gate.apply(sweep, r.labels);
  countInRange(sweep, r.labels, in_range_, r.removals);
  r.times.range_gate = clock.lap();
  r.outlier_points = s.outlier_filter.apply(sweep, r.sampling, Label::unchecked, r.labels);
  countRemoved(in_range_, r.labels, r.removals);
  r.times.outlier_filter = clock.lap();
  r.error_surface_points = s.echo_comparison.apply(sweep, r.labels);
  r.specular_spot_points = s.specular_spots.apply(sweep, r.sampling, sensor_origin, r.labels);
  r.error_surface_points += r.specular_spot_points;
  r.times.echo_comparison = clock.lap();
  // Too few surface echoes for an object: only the mixed pixels among them are to be found.
  if (r.error_surface_points >= s.min_object_points)
  {
    if (configs_.outlier_filter.follows_sampling)
    {
      r.released_surface_beams = s.outlier_filter.releaseIsolatedSurfaceEchoes(sweep, r.sampling, r.labels);
    }
    else
    {
      r.removals.surface_echoes = r.error_surface_points;
      r.removals.surface_echoes_removed = s.outlier_filter.apply(sweep, Label::errorSurface, r.labels);
      r.outlier_points += r.removals.surface_echoes_removed;
    }
    r.times.outlier_filter += clock.lap();
    s.object_extractor.extract(sweep, r.sampling, sensor_origin, r.labels, r.objects);
  }
  if (r.error_surface_points > 0)
    r.mixed_pixel_beams = s.mixed_pixels.release(sweep, r.sampling, r.objects, r.labels);
  r.times.object_extraction = clock.lap();
  if (!r.objects.empty())
    s.type_analyzer.analyzeAll(sweep, sensor_origin, r.labels, evidence(sweep, sensor_origin), r.objects);
  if (r.specular_spot_points > 0)
    s.specular_spots.typeOpenSpots(r.objects);
  r.times.type_analysis = clock.lap();
}

const ReflectionEvidence& Pipeline::evidence(const Sweep& sweep, const Eigen::Vector3f& sensor_origin)
{
  if (!evidence_built_)
  {
    evidence_.build(sweep, result_.labels, sensor_origin, configs_.threads);
    evidence_built_ = true;
  }
  return evidence_;
}

void Pipeline::runObjectStages(const Sweep& sweep, const SweepContext& context, StageClock& clock)
{
  // The parameters' stages work on the objects found (without one the evidence is not built
  // for them) unless they add objects themselves; an added stage may always add objects.
  // A stage that asks nothing of the evidence (the post-filter) gets it as it is, built or not.
  const auto stageEvidence = [&](const ObjectStage& stage) -> const ReflectionEvidence& {
    return stage.needsEvidence() ? evidence(sweep, context.sensorOrigin()) : evidence_;
  };
  for (const std::unique_ptr<ObjectStage>& stage : parameter_stages_)
    if (!result_.objects.empty() || stage->runsWithoutObjects())
      stage->process(sweep, context, stageEvidence(*stage), result_.labels, result_.objects);
  for (const std::unique_ptr<ObjectStage>& stage : object_stages_)
    stage->process(sweep, context, stageEvidence(*stage), result_.labels, result_.objects);
  result_.times.object_stages = clock.lap();
}

void Pipeline::label(const Sweep& sweep, const Eigen::Vector3f& sensor_origin, StageClock& clock)
{
  PipelineResult& r = result_;
  // The evidence is built when the first point behind an object needs it (not at all without an
  // object, nor when nothing lies behind the objects: map objects all round the sensor).
  stages_.cone_labelling.apply(
      sweep, sensor_origin,
      [this, &sweep, &sensor_origin]() -> const ReflectionEvidence& { return evidence(sweep, sensor_origin); },
      r.objects, r.labels, r.assignment);
  r.times.cone_labelling = clock.lap();
  // Unbuilt, no point lies behind an object: the chains follow none and ask nothing.
  const ReflectionEvidence& sweep_evidence = evidence_;
  r.reflection_chains = stages_.reflection_chains.apply(sweep, sensor_origin, sweep_evidence, r.objects, r.assignment,
                                                        r.labels, r.paths);
  r.times.reflection_chains = clock.lap();
  collectCleaned(sweep, r.labels, r.objects, r.paths, r.cleaned);
  r.times.cleaned_output = clock.lap();
  r.echo_separation = evidence_built_ ? evidence_.echoSeparation() : std::numeric_limits<float>::quiet_NaN();
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
