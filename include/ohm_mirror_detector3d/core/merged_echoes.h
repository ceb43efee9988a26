// One echo of a surface merged with a reflection in it (the cone labelling and the phantom planes
// ask for it). A sensor resolves two returns of a beam only its echo separation apart
// (ReflectionEvidence::echoSeparation, 0.9 m for the dual-return lidars); nearer together they
// come back as one echo at a range between them, weighted by their intensities. Where a pane (or
// shiny metal) returns a surface echo and reflects the beam onto something less than that behind
// it, the echo lies short of the reflection: reflected across the plane as measured it lands short
// of what it shows, and no back-projection of the measured point can place it.
#pragma once

#include <Eigen/Core>

#include "ohm_mirror_detector3d/core/reflection_evidence.h"
#include "ohm_mirror_detector3d/core/reflective_object.h"

namespace ohm_mirror_detector3d
{
namespace core
{
// Whether point p behind `object`, with `intensity`, is faint enough against what is seen through
// the object (TypeEvidence::seenThroughBrightness) to be such an echo: false without intensity or
// without anything seen through the object.
bool faintAsMergedReflection(const ReflectiveObject& object, const Eigen::Vector3f& p, float intensity,
                             const Eigen::Vector3f& origin);

// Where the reflection merged into p's echo has its own echo: p moved along its beam to where,
// reflected across `object`, it lands best on what the sensor saw, within what the echo
// separation leaves of p's distance behind the plane; NaN when it lands nowhere within reach (or
// the sweep shows no echo separation).
Eigen::Vector3f mergedReflection(const ReflectionEvidence& evidence, const ReflectiveObject& object,
                                 const Eigen::Vector3f& p);

// For a point p that lands as measured (`measured`, its own test against `object`, phantom or
// ambiguous): the exact landing along its beam when it lies a quarter of the landing tolerance or
// more further (a merged echo short of its reflection by less than the tolerance), else NaN.
Eigen::Vector3f mergedLanding(const ReflectionEvidence& evidence, const ReflectiveObject& object,
                              const Eigen::Vector3f& p, const ReflectionTest& measured);

// An object that returned a surface echo on the beams of at least this share of its points behind
// (TypeEvidence::surface_backed_share) returns one wherever it is seen: a mirror or shiny metal,
// or a pane seen head-on. Only there may a single echo just behind it be its surface echo merged
// with a reflection (mayBeMergedReflection); a pane seen at an angle returns none to merge with.
constexpr float kMergingSurfaceBackedShare = 0.5f;

// Whether point p behind `object`, seen through it by its own test (ReflectionOutcome::transmitted),
// may be a merged echo of a surface that returns echoes everywhere (kMergingSurfaceBackedShare)
// and a reflection that outshines it (a mirror's: the echo lies short of the reflection by a tenth
// or so of its distance behind the plane, see mayBeMergedReflection in merged_echoes.cpp): within
// the echo separation behind the plane, and no longer seen through once moved that little along
// its beam (it lands on seen geometry, or behind it). False without an echo separation.
bool mayBeMergedReflection(const ReflectionEvidence& evidence, const ReflectiveObject& object,
                           const Eigen::Vector3f& p);

}  // namespace core
}  // namespace ohm_mirror_detector3d
