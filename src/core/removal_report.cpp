#include "ohm_mirror_detector3d/core/removal_report.h"

#include <iomanip>
#include <sstream>

namespace ohm_mirror_detector3d
{
namespace core
{
namespace
{
std::vector<const ParamInfo*> outlierFilterParameters()
{
  return { findParameter("outlierFilter_searchRadius"), findParameter("outlierFilter_minNeighbors") };
}

void check(RemovedPoints what, std::size_t removed, std::size_t of, std::size_t min_judged, double limit,
           std::vector<ImplausibleRemoval>& found)
{
  if (of < min_judged || static_cast<double>(removed) <= limit * static_cast<double>(of))
    return;
  found.push_back(ImplausibleRemoval{ what, removed, of, outlierFilterParameters() });
}
const char* whatWasRemoved(RemovedPoints what)
{
  switch (what)
  {
    case RemovedPoints::in_range_points:
      return "of the points in range";
    case RemovedPoints::second_returns:
      return "of the second returns (the echoes that reveal mirrors and glass)";
    case RemovedPoints::surface_echoes:
      return "of the surface echoes (errorSurface) in its second pass";
  }
  return "";
}
}  // namespace

std::vector<ImplausibleRemoval> implausibleRemovals(const RemovalCounts& counts)
{
  std::vector<ImplausibleRemoval> found;
  check(RemovedPoints::in_range_points, counts.outlier_removed, counts.in_range_points, kMinInRangeJudged,
        kImplausibleInRangeShare, found);
  check(RemovedPoints::second_returns, counts.second_returns_removed, counts.second_returns, kMinSecondReturnsJudged,
        kImplausibleSecondReturnShare, found);
  check(RemovedPoints::surface_echoes, counts.surface_echoes_removed, counts.surface_echoes, kMinSurfaceEchoesJudged,
        kImplausibleSurfaceEchoShare, found);
  return found;
}

std::string describeRemoval(const ImplausibleRemoval& removal, const Params& params)
{
  std::ostringstream text;
  text << "the outlier filter removed " << std::fixed << std::setprecision(1) << 100.0 * removal.share() << " % "
       << whatWasRemoved(removal.what) << " (" << removal.removed << " of " << removal.of << ") with ";
  bool automatic = true;
  for (std::size_t i = 0; i < removal.parameters.size(); ++i)
  {
    const ParamInfo& param = *removal.parameters[i];
    text << (i > 0 ? ", " : "") << param.name << " = ";
    if (param.isAutomatic(params))
      text << "automatic";
    else
    {
      automatic = false;
      text << std::defaultfloat << std::setprecision(6) << param.value(params) << " " << param.unit;
    }
  }
  if (automatic)
    text << ": the sweep's sampling was not what it seemed (an unorganised or unevenly sampled cloud?)";
  else
    text << ": these parameters do not fit the sensor; leave them unset (or 0) to follow the sweep's sampling";
  return text.str();
}

std::vector<std::string> removalWarnings(const RemovalCounts& counts, const Params& params)
{
  std::vector<std::string> warnings;
  for (const ImplausibleRemoval& removal : implausibleRemovals(counts))
    warnings.push_back(describeRemoval(removal, params));
  return warnings;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
