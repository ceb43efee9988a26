// Intensity evidence (issue 17): what the intensities of an object's echoes say about mirror
// against glass, beside the geometric evidence of the points behind it.
//
// Per object and sweep (IntensityFeatures on the object), from every return of either echo
// within plane_threshold of its plane and inside its rectangle:
// - normalised intensity q = intensity * range^2 / the sweep's median intensity * range^2 (a
//   diffuse surface's, roughly: the scanner's gain and units cancel), over cos(incidence);
// - faint_share: of the echoes beyond the specular peak (incidence > kOffPeakDeg), the share that
//   is faint (kFaintMin <= q < kFaint): a mirror's silvered back gives a faint haze over its whole
//   face (about 2 % of the reference in the simulator), glass almost nothing off the peak: what
//   lies on its plane there is its frame, as bright as a wall, or its own far fainter haze, seen
//   close by only;
// - haze: the median q of those faint echoes;
// - echo_ratio: the median far / near intensity over the beams whose near echo is on the object
//   and whose far echo lies behind it.
// The log-odds of mirror against glass sums, for each feature the sweep has (enough echoes), the
// log-likelihood ratio of two Gaussians (IntensityModel: log10 of haze and echo_ratio, faint_share
// as it is) with one spread per feature, each clamped to +-kMaxFeatureLogOdds; the sum to
// +-kMaxLogOdds, so that one sweep never decides alone beyond that and a multi-sweep map can add
// sweeps. An object the geometry left unknown is typed from it when |log-odds| reaches
// type_log_odds (IntensityFeatures::typed).
#pragma once

#include "ohm_mirror_detector3d/core/object_stage.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// A Gaussian per type of one feature, with a common spread.
struct FeatureModel
{
  float mirror = 0.0f;
  float glass = 0.0f;
  float sigma = 1.0f;

  // log p(x | mirror) - log p(x | glass).
  float logLikelihoodRatio(float x) const;
};

struct IntensityModel
{
  FeatureModel haze;         // log10(haze)
  FeatureModel faint_share;  // the share itself
  FeatureModel echo_ratio;   // log10(echo_ratio)
};

struct IntensityEvidenceConfig
{
  bool enabled = false;
  float plane_threshold = 0.05f;  // [m] an echo on the object's plane
  float echo_threshold = 0.05f;   // [m] a beam's far echo lies behind its near one (d_thres)
  float type_log_odds = 2.2f;     // |log-odds| that types an unknown object
  IntensityModel model;
};

constexpr float kOffPeakDeg = 5.0f;
constexpr float kFaint = 0.1f;
constexpr float kFaintMin = 0.004f;
constexpr std::size_t kMinFeatureEchoes = 5;
constexpr float kMaxFeatureLogOdds = 3.0f;
constexpr float kMaxLogOdds = 6.0f;
// Every kReferenceStride-th beam gives the sweep's reference intensity (a median needs no more).
constexpr std::size_t kReferenceStride = 7;

// Median intensity * range^2 over the returns of every kReferenceStride-th beam (NaN: none).
float intensityReference(const Sweep& sweep);

// The features and log-odds of one object (its intensity member is not touched).
IntensityFeatures intensityFeatures(const Sweep& sweep, const Eigen::Vector3f& sensor_origin,
                                    const ReflectiveObject& object, float reference,
                                    const IntensityEvidenceConfig& config);

class IntensityEvidence : public ObjectStage
{
public:
  explicit IntensityEvidence(const IntensityEvidenceConfig& config) : config_(config) {}

  const char* name() const override { return "intensity_evidence"; }

  void process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
               SweepLabels& labels, std::vector<ReflectiveObject>& objects) override;

private:
  IntensityEvidenceConfig config_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
