// The original node's values that mean something else in this method, mapped to what they meant
// there when they are given under the original's names (README "Replacing the original node").
// In the core so that every front end maps them alike: the node and prefilter_bag (the names
// their ParamSource holds) and the Python Params (the names of its dict).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/params.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// Changes `params`, as a front end read them and Params::validate() passed them, where a value
// was given under a legacy name alone (is_set(name): the front end was given that name; no other
// name of the same parameter is set: a value set under its new name keeps its meaning):
// - outlierFilter_minNeighbors above 1 with outlierFilter_searchRadius set: a density the original
//   tuned for its one scanner speed; both become automatic, the neighbourhood in the sweep's own
//   beam grid, which asks for one neighbour among the 8 beams around and so removes no more than a
//   demand of several neighbours (1 neighbour within a radius is no density and is honoured);
// - max_Dist_ICP below icp_max_distance's default (0.1 m): a correspondence limit between two
//   clouds inside PCL's ICP, applied after the clouds were aligned; here it is how far a single
//   reflected return may land from what the sensor saw, noise of both included, and below the
//   default a mirror of the original's sweeps is typed glass (0.05 m at 100 scans per half rotation).
// Returns one line per mapped parameter for the start-up log.
std::vector<std::string> mapLegacyValues(const std::function<bool(const std::string&)>& is_set, Params& params);

}  // namespace core
}  // namespace ohm_mirror_detector3d
