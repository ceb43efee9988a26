// Surface echoes that came without a second echo: the specular spot of a pane or a mirror seen
// head-on with nothing in range behind it (a window to the sky, a partition in front of an open
// hall). The echo comparison finds a reflective surface only where a beam returned two echoes
// that differ; such a spot returns one echo, so it finds nothing there.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ohm_mirror_detector3d/core/reflective_object.h"
#include "ohm_mirror_detector3d/core/sweep.h"
#include "ohm_mirror_detector3d/core/sweep_sampling.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct SpecularSpotConfig
{
  bool enabled = true;
  // A spot's returns are at least this many times as bright (intensity x range^2, so that range
  // does not count) as the median single return in the window around the spot's brightest one
  // (the sweep's median single return where most of the window returned none: a window to the sky
  // wider than it). params.specular_spot_ratio.
  // A pane or a mirror met head-on sends back the specular share of the beam: in the simulator
  // 10-40 times a wall's diffuse return at the centre. Real scanners show the same highlight on
  // glass met head-on; how bright depends on the scanner (lower the ratio where it is weaker).
  double min_brightness_ratio = 8.0;
  // Half the side of that window [rad], in rows and columns of the beam grid.
  double window = 0.0524;  // 3 degrees
  // The brightest return of the spot is where the beam met the surface perpendicularly (that is
  // where the specular share comes back): the angle between its beam and the normal of the
  // plane fitted to the spot is at most this [rad]. A bright stripe on a diffuse surface (a white
  // board beside a dark wall) lies at any angle.
  double max_incidence = 0.1745;  // 10 degrees
  // At least this share of the beams in a band `window` wide around the spot's box on the grid
  // returned nothing or only from more than open_depth behind the spot's plane: the rays around
  // the spot went through its plane. Without it the spot is a bright patch on an opaque surface.
  double min_open_share = 0.1;
  double open_depth = 0.5;  // [m]
  // A spot needs this many returns (the object extraction's minimum).
  std::size_t min_points = 9;
};

// Finds specular spots on the beam grid and labels their returns errorSurface, so that the object
// extraction fits planar objects to them as to the near echoes of double echoes, and the type
// analysis decides what they are from what lies behind them. Owns its buffers.
class SpecularSpots
{
public:
  explicit SpecularSpots(const SpecularSpotConfig& config);

  // Works on beams whose first echo is unchecked and that returned no second echo of their own
  // (none, echo 1 repeated, or one within the echo comparison's threshold: left unchecked by it).
  // Needs a grid (sampling) and intensities; without them it finds nothing. Seeds are the single
  // returns that are local maxima of intensity x range^2 and at least min_brightness_ratio times
  // as bright as the median single return in the window around them; a spot is the seed's
  // connected single returns (8-neighbourhood on the grid) at least that bright. A spot that is
  // plausible (see the config) and touches none of the echo comparison's surface echoes is
  // labelled errorSurface with its rim (the single returns next to it on its plane). Returns the
  // number of returns it labelled.
  std::size_t apply(const Sweep& sweep, const SweepSampling& sampling, const Eigen::Vector3f& sensor_origin,
                    SweepLabels& labels);

  // After the type analysis: an object that the last apply()'s spots gave most of its surface
  // echoes, that was left unknown and that has no phantom behind it is glass
  // (TypeEvidence::typed_as_open_spot). A spot is kept only where the rays around it went through
  // its plane; had it been a mirror, they would have come back from the room it faces, as
  // phantoms behind it. Returns the number of objects typed.
  std::size_t typeOpenSpots(std::vector<ReflectiveObject>& objects) const;

private:
  // The beam's first echo is unchecked and the echo comparison left its second alone.
  static bool single(const SweepLabels& labels, std::size_t beam);
  struct SpotPlane
  {
    Eigen::Vector3d point;
    Eigen::Vector3d normal;
  };
  // The plane of the spot in spot_ when the spot is planar, head-on at its brightest return, and
  // surrounded by rays that went through that plane; nothing otherwise.
  std::optional<SpotPlane> plausible(const Sweep& sweep, const SweepLabels& labels,
                                     const Eigen::Vector3f& sensor_origin, std::size_t brightest,
                                     std::size_t band_rows, std::size_t band_cols) const;

  SpecularSpotConfig config_;
  std::vector<float> window_;          // scratch for medians
  std::vector<std::uint8_t> state_;    // per beam: 0 free, 1 in a spot looked at, 2 in the current one
  std::vector<std::uint8_t> in_spot_;  // per beam: its first echo was labelled by a spot
  std::vector<std::uint32_t> touched_; // the beams whose state_ (and in_spot_) this sweep set
  std::vector<std::uint32_t> spot_;    // the current spot's beams
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
