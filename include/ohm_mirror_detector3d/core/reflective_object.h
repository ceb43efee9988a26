// A planar specular or transparent object found in a sweep.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
enum class ObjectType : std::uint8_t
{
  unknown = 0,  // discontinuous echoes on a plane, too little evidence to decide
  mirror = 1,   // reflects and transmits nothing: the points behind it are phantoms (also shiny metal)
  glass = 2,    // the sensor sees through it (and may see reflections in it too)
};

const char* objectTypeName(ObjectType type);

// How far from the surface the sensor saw in its direction a point reflected across an object's
// plane (q) may lie and still lie on it [m]: base + per metre of q's range (noise, sampling) +
// per metre the point lies behind the plane (the plane's angular uncertainty: an error of the
// plane's tilt moves q by twice the tilt times the distance behind).
struct LandingTolerance
{
  float base = 0.1f;
  float per_range = 0.005f;
  float per_behind = 0.0f;

  float at(float range, float behind) const { return base + per_range * range + per_behind * behind; }
};

// Why the type decision came out as it did (object_type.h): what the points behind the object
// said, on an even sample of at most 512 of them, the counts scaled to all of them.
// A return's brightness for the rules that compare brightnesses (TypeEvidence's medians, the
// cone labelling, merged echoes): its intensity times its squared range from `origin`, so that the
// range's falloff cancels. NaN without an intensity.
inline float rangeCompensatedBrightness(const Eigen::Vector3f& p, float intensity, const Eigen::Vector3f& origin)
{
  return intensity * (p - origin).squaredNorm();
}

struct TypeEvidence
{
  std::size_t mirrored_points = 0;     // points behind the plane (inside its vision cone), reflected across it
  std::size_t tested_points = 0;       // of those, the sample whose reflections were tested
  std::size_t phantom_points = 0;      // estimated: land on geometry seen in front
  std::size_t transmitted_points = 0;  // estimated: seen through (what lies where they land is further away)
  std::size_t ambiguous_points = 0;    // estimated: land on a surface that continues through the plane
  std::size_t undecided_points = 0;    // estimated: where they land is occluded, out of view, or without return
  // Of an object the type analysis left unknown or found a mirror among points that disprove
  // it (inside the rectangle only, then): estimated, the undecided points whose phantom
  // light would have had to pierce a surface the sensor saw on its way from the plane to where
  // they land (ReflectionTestOptions::check_path), so real as the cone labelling counts them.
  std::size_t path_blocked_points = 0;
  // Share of the tested points that land on what the sensor saw (phantoms and ambiguous).
  float inlier_fraction = std::numeric_limits<float>::quiet_NaN();
  // Share of the real points (transmitted; occluded too when few are transmitted or phantoms)
  // among the phantoms and real points inside the rectangle (away from its border, where points
  // beside the surface are seen): what types it.
  float real_fraction = std::numeric_limits<float>::quiet_NaN();
  // Of the points behind seen through the rectangle's inside (beyond the reach of merged echoes,
  // object_type.cpp), the share whose beam also returned an echo on the plane (NaN: none). Shiny
  // metal is seen at every incidence, so nearly all of them; glass returns a surface echo only
  // near perpendicular incidence (intensity_evidence.h).
  float surface_backed_share = std::numeric_limits<float>::quiet_NaN();
  // Mean squared distance between the sampled phantoms and what the sensor saw where they land [m^2].
  float landing_fitness = std::numeric_limits<float>::quiet_NaN();
  // The intensity of the sampled phantoms against what the surfaces they land on return when seen
  // directly (reflection_evidence.h: landingIntensityShare): how many have a share, its median,
  // and the fraction of them that are too dim for a mirror or shiny metal, reflections in glass
  // (NaN, NaN without any), and whether that made the object glass (object_type.cpp).
  std::size_t phantom_share_points = 0;
  float phantom_intensity_share = std::numeric_limits<float>::quiet_NaN();
  float dim_phantom_fraction = std::numeric_limits<float>::quiet_NaN();
  bool typed_by_dim_phantoms = false;
  // Whether an object the points inside its rectangle left unknown (too few decided there) was
  // typed mirror by its phantoms' brightness: bright enough for no reflection in glass, and landing
  // as a mirror's phantoms land (object_type.cpp).
  bool typed_by_bright_phantoms = false;
  // Whether the geometry's mirror became glass because points behind it that a phantom's light
  // could not have reached (path-blocked) outnumbered its phantoms, most of which landed on
  // surfaces that map onto themselves (object_type.cpp, kMinPathBlockedForGlass).
  bool typed_by_blocked_paths = false;
  // Whether the object was a specular spot (specular_spots.h) with no phantom behind it that the
  // type analysis left unknown, and was typed glass for it: the rays around the spot went through
  // its plane and returned nothing or from beyond it (a window to open space).
  bool typed_as_open_spot = false;
  // The type the geometry of the points behind gave, before their intensities were looked at.
  ObjectType geometric_type = ObjectType::unknown;
  // Median brightness (intensity x range^2) of the sampled phantoms and of the sampled points seen
  // through (NaN: fewer than 10 with an intensity). Behind glass, a point without evidence of its
  // own that is far fainter than what is seen through is a reflection (cone_labelling.cpp).
  float phantom_brightness = std::numeric_limits<float>::quiet_NaN();
  float transmitted_brightness = std::numeric_limits<float>::quiet_NaN();
  // The median brightness of what those phantoms land on, seen directly (NaN: fewer than 10).
  float landing_brightness = std::numeric_limits<float>::quiet_NaN();

  // How bright what is seen through the object is, for the rules that tell reflections in glass by
  // their faintness (cone_labelling.cpp, merged_echoes.cpp): the sampled points seen through, unless
  // they came out fainter than the sampled phantoms, which no light seen through a pane does; then
  // they were reflections themselves, and what the phantoms land on, seen directly, stands for them
  // (NaN where neither is known). In a pane close by (0.8 m, random scene 9702 of the 128-ring
  // lidar) the reflections of the room behind the sensor that landed beyond what it saw counted as
  // seen through (median 14 against the phantoms' 23), while the outdoors really seen through was
  // at 3900 and the room seen directly at 820. Where the sampled points seen through are not
  // suspect they stay the reference: the brighter of the two there displaced real points dimmer
  // than the room in front (32-ring lidar, random scenes 7, 13 and 17 of make evaluate).
  float seenThroughBrightness() const
  {
    if (!std::isfinite(transmitted_brightness))
      return landing_brightness;
    const bool reflections_themselves = transmitted_brightness < phantom_brightness;
    return reflections_themselves && std::isfinite(landing_brightness) ? landing_brightness : transmitted_brightness;
  }

  // Whether the plane was refined from the phantoms, and by how much it turned [rad].
  bool plane_refined = false;
  float plane_correction = 0.0f;
};

// How a sweep's intensities relate to the model's raw signal.
struct IntensityScale
{
  // Median raw signal * range^2 over the sampled returns (NaN: none).
  float reference = std::numeric_limits<float>::quiet_NaN();
  // The intensities do not fall with range: a calibrated reflectivity. Told per sweep from the
  // same returns: over a room of mixed surfaces and ranges, the raw signal * range^2 varies less
  // than the raw signal itself (median absolute deviation of the log, 0.09-0.17 against
  // 0.12-0.46 decades in random scenes of all four simulated sensors), a reflectivity the other
  // way round.
  bool range_compensated = false;

  // The raw signal the model expects for an intensity at this range.
  float signal(float intensity, float range) const
  {
    return range_compensated ? intensity / (range * range) : intensity;
  }
};

// What the intensities of the object's echoes said in this sweep (intensity_evidence.h; all NaN
// and zero unless intensity_evidence is on and the input has intensities).
struct IntensityFeatures
{
  std::size_t echoes = 0;    // returns on the plane, inside the rectangle
  std::size_t off_peak = 0;  // of those, beyond the specular peak
  float faint_share = std::numeric_limits<float>::quiet_NaN();
  // The sweep's scale the features are relative to (its reference NaN: none).
  IntensityScale scale;
  float haze = std::numeric_limits<float>::quiet_NaN();
  float echo_ratio = std::numeric_limits<float>::quiet_NaN();
  std::size_t bright_off_peak = 0;  // of the off-peak echoes, those lit like a wall
  // Of those whose beam's near echo they are, the share with a far echo behind the plane.
  float bright_backed_share = std::numeric_limits<float>::quiet_NaN();
  float log_odds = 0.0f;  // of mirror against glass, this sweep alone (0: no evidence)
  bool typed = false;     // the geometry left it unknown; the intensities typed it
  // Lit like a wall off its specular peak, with a reflection behind: typed mirror (shiny metal)
  // where the geometry said glass or nothing (intensity_evidence.h, diffuseReflector).
  bool diffuse_reflector = false;
  // No mirror's haze off its specular peak, and far echoes tens of times its near ones: typed
  // glass where the geometry said mirror (intensity_evidence.h, paneByItsEchoes).
  bool pane_by_echoes = false;
  // Left unknown by the geometry, seen through and leaning to glass by the log-odds: typed glass
  // (intensity_evidence.h, seenThroughLeaningPane).
  bool seen_through_pane = false;
  // Glass that no beam met within kMaxSpecularIncidenceDeg of perpendicular, whose echoes off the
  // specular peak are mostly faint: no surface echo of a pane, but the faint reflection, in a pane
  // not found, of a surface in the room (set by the cone labelling, obliqueFaintSurface; its faint
  // echoes there are dropped as `error`).
  bool oblique_faint_surface = false;
};

struct ReflectiveObject
{
  std::uint32_t id = 0;
  ObjectType type = ObjectType::unknown;

  // Plane n.x + d = 0, (n, d) = plane.head<3>(), plane[3]; n is a unit normal pointing
  // towards the sensor origin.
  Eigen::Vector4f plane = Eigen::Vector4f::Zero();

  // Rectangle: centre, unit axes in the plane (width_axis the more horizontal one, i.e.
  // with the smaller |z|; for a horizontal plane the longer side), full extents along them.
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f width_axis = Eigen::Vector3f::UnitX();
  Eigen::Vector3f height_axis = Eigen::Vector3f::UnitY();
  float width = 0.0f;
  float height = 0.0f;
  // The width of a beam's footprint at the object [m]: a beam whose centre passes up to half
  // of it beside an edge still returns from the object (its surface echo and, off a mirror, a
  // phantom in the beam's direction), so the vision cone reaches that far beyond the edges.
  float footprint = 0.0f;

  // The surface-echo patch: the rectangle fitted to the surface echoes (same axes), kept when a
  // growth stage (plane_crossings.h) grew the rectangle over the part of the plane rays are seen
  // through. Without growth, grown is false and the patch is the rectangle itself.
  bool grown = false;
  Eigen::Vector3f patch_centre = Eigen::Vector3f::Zero();
  float patch_width = 0.0f;
  float patch_height = 0.0f;
  // The growth reached growth_max_extent on some side instead of a boundary on the plane.
  bool growth_capped = false;

  // The errorSurface points the plane was fitted to.
  std::vector<PointRef> surface_inliers;

  // Objects that were this object's phantoms (phantom_planes.h), as they were found: the cone
  // labelling labels the points in their vision cones (and in no object's own) by their own
  // evidence against this object's plane.
  std::vector<ReflectiveObject> phantom_planes;
  // Objects that were surfaces seen through this one (phantom_planes.h): a wall behind a pane
  // whose near echoes formed a plane, the pane's reflections their far echoes. The cone labelling
  // labels the points in their vision cones (and in no object's own) against this object's plane.
  std::vector<ReflectiveObject> seen_through_surfaces;

  // Filled by cone labelling: points of both echoes on the surface and behind it, and what the
  // points behind said each (ReflectionOutcome): phantoms, transmitted, landing on a surface
  // that continues through the plane, and the rest (occluded, out of view, no return).
  std::size_t surface_points = 0;
  std::size_t behind_points = 0;
  std::size_t phantom_points = 0;
  std::size_t transmitted_points = 0;
  std::size_t ambiguous_points = 0;
  std::size_t undecided_points = 0;
  float mean_surface_intensity = std::numeric_limits<float>::quiet_NaN();

  // How far from what the sensor saw a point behind may land, reflected across the plane, and
  // still land on it: set by the type decision (from icp_max_distance and the plane's
  // uncertainty); the cone labelling tests every point behind with it.
  LandingTolerance landing_tolerance;

  TypeEvidence evidence;
  IntensityFeatures intensity;

  // Corners in order around the rectangle: centre -+ w/2 -+ h/2.
  std::array<Eigen::Vector3f, 4> corners() const;
  // The same for the surface-echo patch (the rectangle's corners when it did not grow).
  std::array<Eigen::Vector3f, 4> patchCorners() const;

  // Signed distance of p from the plane, positive on the sensor's side.
  float signedDistance(const Eigen::Vector3f& p) const { return plane.head<3>().dot(p) + plane[3]; }

  // p reflected across the plane.
  Eigen::Vector3f reflect(const Eigen::Vector3f& p) const
  {
    return p - 2.0f * signedDistance(p) * plane.head<3>();
  }

  // Where the ray from `origin` through p crosses the plane (origin and p on either side of it).
  Eigen::Vector3f rayCrossing(const Eigen::Vector3f& origin, const Eigen::Vector3f& p) const
  {
    const float origin_side = signedDistance(origin);
    return origin + (origin_side / (origin_side - signedDistance(p))) * (p - origin);
  }

  // Whether `other` lies in this object's plane: their normals within acos(min_cosine) of each
  // other (either way round), other's centre within max_distance of this plane.
  bool sharesPlaneWith(const ReflectiveObject& other, float min_cosine, float max_distance) const
  {
    return std::fabs(plane.head<3>().dot(other.plane.head<3>())) >= min_cosine &&
           std::fabs(signedDistance(other.centre)) <= max_distance;
  }

};

}  // namespace core
}  // namespace ohm_mirror_detector3d
