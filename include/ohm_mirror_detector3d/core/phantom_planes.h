// Object stage: an object made of another object's phantoms is no surface. At oblique incidence a
// pane splits a beam: the reflected part returns a phantom, the transmitted part a point behind
// the pane, and neither echo lies on the pane. Where the near echoes of such beams lie on one
// plane, object extraction takes them for a reflective surface (a "phantom plane": the mirror
// image, across the pane, of a wall the sensor sees). Its surface echoes lie behind the real
// object's plane and, reflected across it, land on what the sensor saw in front: the per-point
// evidence of reflection_evidence.h says "phantom" for them. Such an object is removed and kept by
// the object it is a phantom of (ReflectiveObject::phantom_planes): the cone labelling labels the
// points in its vision cone by their own evidence against that object's plane (behindReflective,
// back-projected, where they land on what the sensor saw; behindTransparent where it saw
// through), even where they lie outside that object's own cone (a pane's surface echoes cover
// only its near-perpendicular patch). A surface echo that is the other object's surface echo merged
// with its reflection (merged_echoes.h: it lands when moved along its beam) counts as its phantom
// too: such echoes lie on a plane just behind a pane, short of the image of what they show.
//
// Where the transmitted part's path is the shorter, the near echoes lie on what the pane shows
// behind it (a wall seen through a glass wall) and the far echoes are the pane's reflections.
// Those near echoes are real (no phantoms of the pane) and their beams' far echoes are the
// pane's phantoms, not the wall's: such an object, a surface seen through the other, is removed
// too and kept in that object's seen_through_surfaces. Its points are labelled against the
// pane; those beyond it that prove nothing are no real points either (nothing is seen behind a
// wall): behindErrorS.
//
// A pane also shows what the sensor cannot see directly: the back of a box or a person standing
// between the sensor and the pane. Such a phantom plane's echoes, reflected across the pane, land
// just behind the side the sensor does see (occluded, not on it), and their beams' far echoes lie
// further behind the pane, transmitted. Those near echoes count as the pane's phantoms too
// (PhantomPlaneConfig::max_hidden_depth).
//
// Just behind a pane (nearer than min_depth) landing proves nothing: reflected across a plane it
// nearly lies on, an echo lands next to itself. There an echo counts as the pane's reflection by
// its brightness: fainter than a quarter of what the pane lets through, as a merged echo is
// (merged_echoes.h). Pairs shown that way are assigned after the pairs that geometry shows. An
// echo there that is not faint may still be a surface seen through the pane (a wall right behind a
// partition's next pane): its beam's far echo says so, as above, when it lands across the pane
// (on what it shows, or on a floor or side wall the pane maps onto itself) and not across the
// object's own plane.
//
// An echo behind a pane as bright as a wall is no reflection in it: where it lands on a surface,
// that surface's normal comes from a ball of returns (ReflectionTestOptions::wide_normal), so
// that a real panel on a wall that runs through a partition, landing on that same wall in front,
// is not taken for the partition's image of it (phantom_planes.cpp).
//
// The pipeline runs the stage twice: before growth, and after it on the hosts growth grew only
// (PhantomPlaneConfig::grown_hosts_only), whose faint phantom planes are bounded by the grown
// rectangle rather than by the patch's surface echoes.
#pragma once

#include <cstddef>
#include <vector>

#include "ohm_mirror_detector3d/core/object_stage.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct PhantomPlaneConfig
{
  bool enabled = true;
  // phantom_plane_share: the share of an object's (sampled) surface echoes that must be phantoms
  // of another object for it to be one.
  float min_share = 0.5f;
  // A surface echo nearer than this behind the other object's plane is not tested [m]: reflected
  // across a plane it (nearly) lies on, any point lands on itself (behind a pane, a faint one
  // counts by its brightness: kMinFaintDepth).
  float min_depth = 0.3f;
  // An object with more than this many times the other's surface echoes is not its phantom
  // plane: a pane's or a mirror's phantom planes come with about as many near echoes as its
  // patch, or fewer (random scenes 4000-4019: up to 2.3 times). Without it, a real mirror of
  // 15000 surface echoes was taken for the phantoms of a 0.2 m speck on a plane that happened to
  // map it onto a wall (random_48 on the 128-ring lidar).
  // The rays are not required to cross the other plane near its rectangle: a pane's patch is
  // small, the pane and its phantom planes are not (bounded to growth_max_extent beyond the patch,
  // most of the gain on random scenes 4000-4019 was lost; for hosts not typed glass, bounded to
  // 0.5 m beyond the rectangle, a mirror's phantom plane on the 128-ring lidar's random_31 was
  // lost, 541 phantoms). Instead an object typed mirror is no phantom plane of an object typed
  // unknown (phantom_planes.cpp).
  float max_echo_ratio = 4.0f;
  // A near echo behind a pane whose reflection lands at most this far behind a surface the sensor
  // saw is the image of that surface's hidden side (the back of a box, a person, a cupboard): the
  // depth of such things [m]. Reflected across the pane, the surface echoes of a real mirror or
  // metal panel behind it land far behind what the sensor saw there (0.7-2.2 m on the rotating
  // Hokuyo's random scenes 0-49); with no bound three of them (random_3, 7 and 48) were taken for
  // a pane's phantoms and lost.
  float max_hidden_depth = 0.5f;
  // Only hosts that a growth stage grew (ReflectiveObject::grown): the second run, after growth.
  bool grown_hosts_only = false;
};

class PhantomPlanes : public ObjectStage
{
public:
  explicit PhantomPlanes(const PhantomPlaneConfig& config);
  const char* name() const override { return "phantom_planes"; }
  // Tests every object's surface echoes (an even sample of at most kSampledEchoes) against every
  // other object's plane (shares); the pair with the largest share at or above min_share is taken
  // first (the pairs shown by brightness alone after the rest), into the other's phantom_planes or
  // seen_through_surfaces. An object that took another in is kept (it is real), and an object that
  // was taken in takes none. The remaining objects are renumbered by their index.
  void process(const Sweep& sweep, const SweepContext& context, const ReflectionEvidence& evidence,
               SweepLabels& labels, std::vector<ReflectiveObject>& objects) override;

  static constexpr std::size_t kSampledEchoes = 64;
  static constexpr std::size_t kPasses = 4;
  // Behind a pane, an echo less than min_depth but more than this behind its plane [m] that is
  // faint against what the pane lets through counts as its reflection (phantom_planes.cpp); nearer,
  // it is the pane's own surface echo.
  static constexpr float kMinFaintDepth = 0.1f;

  // Of `object`'s sampled surface echoes that lie at least min_depth behind `host`'s plane as seen
  // from `origin` (or, behind a pane, faint and more than kMinFaintDepth behind it):
  struct Shares
  {
    // the share that, reflected across it, land on what the sensor saw (ReflectionOutcome::phantom),
    // or are faint just behind a pane; 0 when `object` has more than max_echo_ratio times `host`'s
    // surface echoes (and `host` is no pane);
    float phantom = 0.0f;
    // of which the share that land (or whose merged reflection does), without the faint echoes
    // just behind a pane that count by their brightness alone (kMinFaintDepth).
    float landed = 0.0f;
    // the share that do not, and whose beam's far echo (min_depth behind both planes) is a phantom
    // of `host` and not of `object`: `object` is a surface seen through `host` (0 when either is
    // typed mirror).
    float seen_through = 0.0f;
  };
  // Either share stops being counted once neither can reach min_share, or when the first of
  // kPasses interleaved passes over the sample finds under half of min_share (then both are below
  // min_share, not exact).
  // `scale`: the sweep's intensity scale (intensityScale), or none.
  Shares shares(const Sweep& sweep, const Eigen::Vector3f& origin, const ReflectionEvidence& evidence,
                const ReflectiveObject& object, const ReflectiveObject& host,
                const IntensityScale* scale = nullptr) const;

private:
  PhantomPlaneConfig config_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
