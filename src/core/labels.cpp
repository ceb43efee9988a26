#include "ohm_mirror_detector3d/core/labels.h"

namespace ohm_mirror_detector3d
{
namespace core
{
const char* labelName(Label label)
{
  switch (label)
  {
    case Label::unchecked: return "unchecked";
    case Label::valid: return "valid";
    case Label::errorSurface: return "errorSurface";
    case Label::behindErrorS: return "behindErrorS";
    case Label::reflectiveSurface: return "reflectiveSurface";
    case Label::behindReflective: return "behindReflective";
    case Label::transparentSurface: return "transparentSurface";
    case Label::behindTransparent: return "behindTransparent";
    case Label::nanPoint: return "nanPoint";
    case Label::error: return "error";
  }
  return "invalid-label";
}

bool keptInCleaned(Label label)
{
  return label != Label::unchecked && label != Label::nanPoint && label != Label::error;
}

}  // namespace core
}  // namespace ohm_mirror_detector3d
