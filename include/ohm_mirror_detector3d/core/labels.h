// Point labels of the pre-filter (DESIGN.md). The numbers are those of the
// original implementation so that old tools reading the `label` field keep working.
#pragma once

#include <cstdint>

namespace ohm_mirror_detector3d
{
namespace core
{
enum class Label : std::uint8_t
{
  unchecked = 0,           // not processed yet
  valid = 1,               // unaffected by any specular or transparent surface
  errorSurface = 2,        // on a specular/transparent surface of unknown type
  behindErrorS = 3,        // behind a surface of unknown type
  reflectiveSurface = 4,   // on a mirror
  behindReflective = 5,    // phantom seen via a mirror
  transparentSurface = 6,  // on glass
  behindTransparent = 7,   // real object behind glass
  nanPoint = 8,            // invalid, out of range or outlier
  error = 9,               // far echo of a discontinuous beam outside every object
};

constexpr int kLabelCount = 10;

const char* labelName(Label label);

// Whether a point with this label goes to mapping (`cleaned`); behindReflective
// points go there back-projected across their mirror.
bool keptInCleaned(Label label);

}  // namespace core
}  // namespace ohm_mirror_detector3d
