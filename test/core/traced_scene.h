// A tiny ray tracer for the core tests of the growth stages: axis-aligned walls, mirrors and
// panes around a sensor at the origin, traced on a grid of directions into a two-echo sweep.
// A mirror or a pane returns a surface echo only near perpendicular incidence (as real ones
// do); elsewhere a mirror's beam returns from where its reflection lands, seen along the
// original direction (a phantom behind the mirror), and a pane's beam from what lies behind.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace test
{
enum class Surface
{
  wall,
  mirror,
  glass,
};

// The rectangle x[axis] == at, low <= x[other] <= high for the two other axes (in order).
struct Panel
{
  int axis;
  float at;
  float low[2];
  float high[2];
  Surface surface;

  bool contains(const Eigen::Vector3f& x) const
  {
    int k = 0;
    for (int a = 0; a < 3; ++a)
    {
      if (a == axis)
        continue;
      if (x[a] < low[k] || x[a] > high[k])
        return false;
      ++k;
    }
    return true;
  }
};

struct TracedScene
{
  std::vector<Panel> panels;
  float surface_echo_degrees = 4.0f;  // incidence below which a mirror or a pane gives a surface echo

  // The first panel hit from `from` along `direction` beyond a small step, or nullptr.
  const Panel* hit(const Eigen::Vector3f& from, const Eigen::Vector3f& direction, float& distance) const
  {
    const Panel* nearest = nullptr;
    distance = std::numeric_limits<float>::infinity();
    for (const Panel& panel : panels)
    {
      if (std::fabs(direction[panel.axis]) < 1e-6f)
        continue;
      const float t = (panel.at - from[panel.axis]) / direction[panel.axis];
      if (t > 1e-4f && t < distance && panel.contains(from + t * direction))
      {
        distance = t;
        nearest = &panel;
      }
    }
    return nearest;
  }

  // Echo 1 and echo 2 of the beam along `direction` from the origin (the same point for a
  // single return, non-finite points for none).
  void trace(const Eigen::Vector3f& direction, Eigen::Vector3f& echo1, Eigen::Vector3f& echo2) const
  {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    echo1 = echo2 = Eigen::Vector3f::Constant(nan);
    const float cos_surface = std::cos(surface_echo_degrees * static_cast<float>(M_PI) / 180.0f);
    Eigen::Vector3f from = Eigen::Vector3f::Zero();
    Eigen::Vector3f d = direction;
    float travelled = 0.0f;
    bool surface_echo = false;
    for (int bounce = 0; bounce < 4; ++bounce)
    {
      float t = 0.0f;
      const Panel* panel = hit(from, d, t);
      if (panel == nullptr)
        break;
      travelled += t;
      from += t * d;
      if (panel->surface == Surface::wall)
      {
        echo2 = travelled * direction;
        if (!surface_echo)
          echo1 = echo2;
        return;
      }
      if (bounce == 0 && std::fabs(d[panel->axis]) >= cos_surface)
      {
        echo1 = from;
        surface_echo = true;
      }
      if (panel->surface == Surface::mirror)
        d[panel->axis] = -d[panel->axis];
    }
    if (surface_echo)
      echo2 = echo1;
  }

  // Beams on a grid of azimuths x elevations [deg] (rows: elevations), at `step` degrees.
  core::Sweep sweep(float azimuth_from, float azimuth_to, float elevation_from, float elevation_to,
                    float step) const
  {
    const float degree = static_cast<float>(M_PI) / 180.0f;
    const std::size_t cols = static_cast<std::size_t>(std::lround((azimuth_to - azimuth_from) / step)) + 1;
    const std::size_t rows = static_cast<std::size_t>(std::lround((elevation_to - elevation_from) / step)) + 1;
    core::Sweep out;
    out.resize(rows, cols);
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < cols; ++c)
      {
        const float elevation = (elevation_from + step * static_cast<float>(r)) * degree;
        const float azimuth = (azimuth_from + step * static_cast<float>(c)) * degree;
        const Eigen::Vector3f direction(std::cos(elevation) * std::cos(azimuth),
                                        std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
        trace(direction, out.echoes[0].points[r * cols + c], out.echoes[1].points[r * cols + c]);
      }
    out.computeRanges(Eigen::Vector3f::Zero());
    return out;
  }
};

// A closed room x in [-back, front], y in [-side, side], z in [-below, above] (walls only).
inline std::vector<Panel> room(float back, float front, float side, float below, float above)
{
  return { { 0, -back, { -side, -below }, { side, above }, Surface::wall },
           { 0, front, { -side, -below }, { side, above }, Surface::wall },
           { 1, -side, { -back, -below }, { front, above }, Surface::wall },
           { 1, side, { -back, -below }, { front, above }, Surface::wall },
           { 2, -below, { -back, -side }, { front, side }, Surface::wall },
           { 2, above, { -back, -side }, { front, side }, Surface::wall } };
}

}  // namespace test
}  // namespace ohm_mirror_detector3d
