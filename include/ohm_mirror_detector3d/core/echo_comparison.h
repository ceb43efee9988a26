// Stage identifyReflections of the paper: compare the two echoes of every beam.
#pragma once

#include <cstddef>

#include "ohm_mirror_detector3d/core/sweep.h"

namespace ohm_mirror_detector3d
{
namespace core
{
struct EchoComparisonConfig
{
  double threshold;  // d_thres [m]
};

class EchoComparison
{
public:
  explicit EchoComparison(const EchoComparisonConfig& config);

  // For every beam whose two echoes are both unchecked: when |d1 - d2| > threshold the nearer
  // echo becomes errorSurface (it lies on the specular/transparent surface) and the farther one
  // error, whichever order the echoes arrive in. Beams with one return (the other echo
  // nanPoint) and beams whose echoes agree are left unchecked. Returns the number of
  // errorSurface points it labelled (n_affected).
  std::size_t apply(const Sweep& sweep, SweepLabels& labels) const;

private:
  float threshold_;
};

}  // namespace core
}  // namespace ohm_mirror_detector3d
