// Each stage's own values, taken from the pipeline's parameters. This is the one place where
// core::Params meets the stages: the stages know only their configs (as KISS-ICP's modules
// do), and a value that is derived rather than given (a default that follows the sweep's
// sampling) is resolved here, once, into the configs the stages are built with: an automatic
// parameter (kAutomatic: not set) becomes a neighbourhood in the sweep's own sampling
// (BeamNeighbourhood: the beams around, a limit that grows with range and the angular step,
// which each sweep's SweepSampling supplies), a value the user set is used as given.
#pragma once

#include "ohm_mirror_detector3d/core/cone_labelling.h"
#include "ohm_mirror_detector3d/core/echo_comparison.h"
#include "ohm_mirror_detector3d/core/intensity_evidence.h"
#include "ohm_mirror_detector3d/core/mixed_pixels.h"
#include "ohm_mirror_detector3d/core/object_extraction.h"
#include "ohm_mirror_detector3d/core/object_map.h"
#include "ohm_mirror_detector3d/core/object_type.h"
#include "ohm_mirror_detector3d/core/outlier_filter.h"
#include "ohm_mirror_detector3d/core/plane_crossings.h"
#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/phantom_planes.h"
#include "ohm_mirror_detector3d/core/range_gate.h"
#include "ohm_mirror_detector3d/core/reflection_chains.h"
#include "ohm_mirror_detector3d/core/shared_normals.h"
#include "ohm_mirror_detector3d/core/specular_spots.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct StageConfigs
{
  RangeGateConfig range_gate;
  OutlierFilterConfig outlier_filter;
  EchoComparisonConfig echo_comparison;
  SpecularSpotConfig specular_spots;
  ObjectExtractionConfig object_extraction;
  MixedPixelConfig mixed_pixels;
  ObjectTypeConfig object_type;
  ConeLabellingConfig cone_labelling;
  PhantomPlaneConfig phantom_planes;
  SharedNormalConfig shared_normals;
  ObjectGrowthConfig growth;  // mirror_growth.h and glass_growth.h
  ReflectionChainConfig reflection_chains;
  ObjectMapConfig object_map;  // post_filter.h
  IntensityEvidenceConfig intensity;
  int threads = 1;  // core/parallel.h: resolved (automatic: automaticThreadCount())
};

// With outlierFilter_searchRadius automatic the outlier filter, its errorSurface pass and the
// patch connectivity of object extraction use the beams around a point on the sweep's grid
// (half width 1: the 8 around; with n_inlier set, as many rings of beams as hold n_inlier),
// step factor kNeighbourStepFactor, noise floor d_thres; with it set, the sphere of radius r.
// n_inlier automatic is kAutomaticMinNeighbors, n_object automatic kAutomaticMinObjectPoints;
// objects are at least kMinBeamsAcross beams across while r is automatic.
StageConfigs stageConfigs(const Params& params);

constexpr double kNeighbourStepFactor = 3.0;
constexpr int kAutomaticMinNeighbors = 1;
// 3 x 3 beams, the smallest patch that is kMinBeamsAcross across both ways.
constexpr int kAutomaticMinObjectPoints = 9;
constexpr int kMinBeamsAcross = 3;
// A lidar's beam is about as wide as its step along a scan line (the divergence matches the
// resolution: the UTM-30LX-EW's 0.25 deg at 0.25 deg; the 128- and 32-ring lidars of
// SENSORS.md about 0.18 deg at 0.18 and 0.16 deg): object rectangles take the footprint as one
// column step (ObjectExtractionConfig::footprint_steps).
constexpr double kFootprintSteps = 1.0;

}  // namespace core
}  // namespace ohm_mirror_detector3d
