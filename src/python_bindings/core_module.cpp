// ohm_mirror_detector3d._core: the ROS-free pipeline on numpy arrays (pybind11).
//
// The pure-Python wrapper ohm_mirror_detector3d/core.py is the public face (parameter
// dataclass, result object); this module does the work that must not cost Python time: checks
// the arrays, fills the pipeline's Sweep straight from the numpy buffers (the only copy the
// core needs, since it owns its Sweep), runs the pipeline with the GIL released and writes the
// outputs with the core's record writer (core/output_records.h), which writes the nodelet's
// `labelled` and `cleaned` PointCloud2s too.
//
// Only pybind11 2.4 API (Ubuntu 20.04 / ROS Noetic).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/core/intensity_evidence.h"
#include "ohm_mirror_detector3d/core/labels.h"
#include "ohm_mirror_detector3d/core/legacy_values.h"
#include "ohm_mirror_detector3d/core/object_map_file.h"
#include "ohm_mirror_detector3d/core/output_records.h"
#include "ohm_mirror_detector3d/core/param_table.h"
#include "ohm_mirror_detector3d/core/params.h"
#include "ohm_mirror_detector3d/core/pipeline.h"
#include "ohm_mirror_detector3d/core/removal_report.h"

namespace py = pybind11;
using namespace ohm_mirror_detector3d;

namespace
{
using Records = py::array_t<core::OutputRecord>;

// The array's bytes, for the record writer (which sets every byte, padding included).
std::uint8_t* recordBytes(Records& records)
{
  return reinterpret_cast<std::uint8_t*>(records.mutable_data());
}

std::string describeShape(const py::array& a)
{
  std::ostringstream s;
  s << "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k)
    s << (k ? ", " : "") << a.shape(k);
  s << (a.ndim() == 1 ? ",)" : ")");
  return s.str();
}

std::string dtypeName(const py::array& a)
{
  return py::str(a.dtype()).cast<std::string>();
}

// A points array: float32, (N, 3) or, when `grid_allowed`, (rows, cols, 3). Returns the
// array viewed as (N, 3) (no copy) and sets rows/cols ((1, N) for a flat array).
py::array checkPoints(const py::object& object, const char* name, bool grid_allowed, std::size_t& rows,
                      std::size_t& cols)
{
  if (!py::isinstance<py::array>(object))
    throw py::type_error(std::string(name) + " must be a numpy array of float32 x y z, not " +
                         std::string(Py_TYPE(object.ptr())->tp_name));
  py::array a = py::reinterpret_borrow<py::array>(object);
  if (!py::isinstance<py::array_t<float>>(a))  // float32 in native byte order
    throw py::type_error(std::string(name) + " has dtype " + dtypeName(a) +
                         "; expected float32 x y z (convert with .astype(numpy.float32))");
  const bool flat = a.ndim() == 2 && a.shape(1) == 3;
  const bool grid = grid_allowed && a.ndim() == 3 && a.shape(2) == 3;
  if (!flat && !grid)
    throw py::value_error(std::string(name) + " has shape " + describeShape(a) + "; expected (N, 3)" +
                          (grid_allowed ? " or (rows, cols, 3)" : ""));
  rows = grid ? static_cast<std::size_t>(a.shape(0)) : 1;
  cols = grid ? static_cast<std::size_t>(a.shape(1)) : static_cast<std::size_t>(a.shape(0));
  return a;
}

// Optional per-point values (intensities): any real numeric dtype, `count` elements in any
// shape that has that many (N, or rows x cols). Returned as float32, a copy only when the
// input is not float32 already.
py::object checkIntensities(const py::object& object, const char* name, std::size_t count)
{
  if (object.is_none())
    return object;
  if (!py::isinstance<py::array>(object))
    throw py::type_error(std::string(name) + " must be a numpy array or None");
  py::array a = py::reinterpret_borrow<py::array>(object);
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + " has dtype " + dtypeName(a) + "; expected a real number per point");
  if (static_cast<std::size_t>(a.size()) != count || a.ndim() < 1)
    throw py::value_error(std::string(name) + " has shape " + describeShape(a) + " but there are " +
                          std::to_string(count) + " points; expected one value per point");
  return py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
}

py::array_t<std::int64_t, py::array::c_style> checkIntegers(const py::object& object, const char* name, std::size_t count)
{
  if (!py::isinstance<py::array>(object))
    throw py::type_error(std::string(name) + " must be a numpy array of integers");
  py::array a = py::reinterpret_borrow<py::array>(object);
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + " has dtype " + dtypeName(a) + "; expected integers (one per point)");
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != count)
    throw py::value_error(std::string(name) + " has shape " + describeShape(a) + "; expected (" +
                          std::to_string(count) + ",), one value per point");
  return py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
}

// Copies N x 3 float32 points (any strides) into `out`. A point is either a return (x y z all
// finite) or no return (all three non-finite, REP-117); returns the index of the first point
// with some but not all coordinates finite, or -1.
std::int64_t copyPoints(const py::array& points, std::vector<Eigen::Vector3f>& out)
{
  const std::size_t n = out.size();
  const char* base = static_cast<const char*>(points.data());
  const py::ssize_t row_stride = points.ndim() == 3 ? points.strides(1) : points.strides(0);
  const py::ssize_t grid_stride = points.ndim() == 3 ? points.strides(0) : 0;
  const std::size_t cols = points.ndim() == 3 ? static_cast<std::size_t>(points.shape(1)) : n;
  const py::ssize_t coord_stride = points.strides(points.ndim() - 1);
  std::int64_t bad = -1;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t row = cols ? i / cols : 0;
    const std::size_t col = cols ? i % cols : 0;
    const char* p = base + static_cast<py::ssize_t>(row) * grid_stride + static_cast<py::ssize_t>(col) * row_stride;
    Eigen::Vector3f& q = out[i];
    for (int c = 0; c < 3; ++c)
      std::memcpy(&q[c], p + c * coord_stride, sizeof(float));
    const int finite = std::isfinite(q.x()) + std::isfinite(q.y()) + std::isfinite(q.z());
    if (bad < 0 && finite != 0 && finite != 3)
      bad = static_cast<std::int64_t>(i);
  }
  return bad;
}

// The float32 values of checkIntensities' result (C-contiguous), nullptr for None. Taken with
// the GIL held; the caller's reference keeps the array alive.
const float* intensityData(const py::object& intensities)
{
  return intensities.is_none() ? nullptr : py::reinterpret_borrow<py::array_t<float>>(intensities).data();
}

// Runs without the GIL: only raw pointers.
void copyIntensities(const float* intensities, std::vector<float>& out)
{
  if (intensities == nullptr)
    std::fill(out.begin(), out.end(), std::numeric_limits<float>::quiet_NaN());
  else if (!out.empty())
    std::memcpy(out.data(), intensities, out.size() * sizeof(float));
}

void throwPartlyFinite(const char* name, std::int64_t index, const Eigen::Vector3f& p)
{
  std::ostringstream message;
  message << name << " point " << index << " = (" << p.x() << ", " << p.y() << ", " << p.z()
          << ") is partly NaN/Inf: a missing return must be non-finite in all of x y z (REP-117)";
  throw py::value_error(message.str());
}

py::object boundOf(const core::ParamBound& bound)
{
  if (!bound.present)
    return py::none();
  py::dict d;
  d["value"] = bound.value;
  d["inclusive"] = bound.inclusive;
  return std::move(d);
}

py::object textOrNone(const char* text)
{
  return *text == '\0' ? py::object(py::none()) : py::object(py::str(text));
}

// The parameter table (core/param_table.h) as a list of dicts, one per row, in its order.
py::list parameterTable()
{
  py::list rows;
  for (const core::ParamInfo& param : core::parameterTable())
  {
    py::dict row;
    row["name"] = param.name;
    row["symbol"] = textOrNone(param.symbol);
    row["aliases"] = param.aliases;
    row["names"] = param.names();
    row["label"] = param.label;
    row["type"] = core::paramTypeName(param.type);
    row["scope"] = core::paramScopeName(param.scope);
    row["reconfigurable"] = param.reconfigurable;
    if (param.type == core::ParamType::integer)
      row["default"] = static_cast<int>(param.default_value.number);
    else if (param.type == core::ParamType::real)
      row["default"] = param.default_value.number;
    else
      row["default"] = param.default_value.text;
    row["when_unset"] = textOrNone(param.default_value.when_unset);
    row["automatic"] = textOrNone(param.automatic);  // what an automatic parameter at 0 follows
    row["lower"] = boundOf(param.lower);
    row["upper"] = boundOf(param.upper);
    row["above"] = textOrNone(param.above);
    row["unit"] = param.unit;
    row["doc"] = param.doc;
    row["allowed"] = param.allowed;
    row["checked_by"] = param.checked_by;
    row["field"] = textOrNone(param.field);
    rows.append(row);
  }
  return rows;
}

// Empty when `value` is usable for the start-up parameter `name`, otherwise why not; the check
// of its row, or nothing for a parameter without one.
std::string checkStartUp(const std::string& name, double value)
{
  const core::ParamInfo* param = core::findParameter(name);
  if (param == nullptr)
    throw py::key_error("no parameter " + name);
  return param->check != nullptr ? param->check(value) : std::string();
}

py::dict objectToDict(const core::ReflectiveObject& object)
{
  py::dict d;
  d["id"] = object.id;
  d["type"] = static_cast<int>(object.type);
  d["type_name"] = core::objectTypeName(object.type);
  const std::array<Eigen::Vector3f, 4> corners = object.corners();
  py::array_t<double> c(std::vector<py::ssize_t>{ 4, 3 });
  auto cw = c.mutable_unchecked<2>();
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 3; ++j)
      cw(k, j) = corners[static_cast<std::size_t>(k)][j];
  d["corners"] = c;
  d["width"] = static_cast<double>(object.width);
  d["height"] = static_cast<double>(object.height);
  const std::array<Eigen::Vector3f, 4> patch = object.patchCorners();
  py::array_t<double> pc(std::vector<py::ssize_t>{ 4, 3 });
  auto pw = pc.mutable_unchecked<2>();
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 3; ++j)
      pw(k, j) = patch[static_cast<std::size_t>(k)][j];
  d["patch_corners"] = pc;
  d["patch_width"] = static_cast<double>(object.grown ? object.patch_width : object.width);
  d["patch_height"] = static_cast<double>(object.grown ? object.patch_height : object.height);
  d["growth_capped"] = object.growth_capped;
  py::array_t<double> plane(4);
  py::array_t<double> centre(3);
  for (int k = 0; k < 4; ++k)
    plane.mutable_at(k) = object.plane[k];
  for (int k = 0; k < 3; ++k)
    centre.mutable_at(k) = object.centre[k];
  d["plane"] = plane;
  d["centre"] = centre;
  d["surface_points"] = object.surface_points;
  d["behind_points"] = object.behind_points;
  d["mean_surface_intensity"] = static_cast<double>(object.mean_surface_intensity);
  d["phantom_points"] = object.phantom_points;
  d["transmitted_points"] = object.transmitted_points;
  d["ambiguous_points"] = object.ambiguous_points;
  d["undecided_points"] = object.undecided_points;
  // The objects it took in (phantom_planes.h): of which kind, where, how large, of how many echoes.
  py::list taken;
  for (const auto* kind : { &object.phantom_planes, &object.seen_through_surfaces })
    for (const core::ReflectiveObject& other : *kind)
    {
      py::dict t;
      t["kind"] = kind == &object.phantom_planes ? "phantom_plane" : "seen_through";
      t["centre"] = py::make_tuple(other.centre.x(), other.centre.y(), other.centre.z());
      t["width"] = static_cast<double>(other.width);
      t["height"] = static_cast<double>(other.height);
      t["surface_echoes"] = other.surface_inliers.size();
      taken.append(t);
    }
  d["taken_in"] = taken;
  const core::TypeEvidence& e = object.evidence;
  d["mirrored_points"] = e.mirrored_points;
  d["tested_points"] = e.tested_points;
  d["inlier_fraction"] = static_cast<double>(e.inlier_fraction);
  d["real_fraction"] = static_cast<double>(e.real_fraction);
  d["surface_backed_share"] = static_cast<double>(e.surface_backed_share);
  d["phantom_intensity_share"] = static_cast<double>(e.phantom_intensity_share);
  d["phantom_share_points"] = e.phantom_share_points;
  d["dim_phantom_fraction"] = static_cast<double>(e.dim_phantom_fraction);
  d["typed_by_dim_phantoms"] = e.typed_by_dim_phantoms;
  d["typed_by_bright_phantoms"] = e.typed_by_bright_phantoms;
  d["typed_by_blocked_paths"] = e.typed_by_blocked_paths;
  d["typed_as_open_spot"] = e.typed_as_open_spot;
  d["path_blocked_points"] = e.path_blocked_points;
  d["phantom_brightness"] = static_cast<double>(e.phantom_brightness);
  d["transmitted_brightness"] = static_cast<double>(e.transmitted_brightness);
  d["landing_brightness"] = static_cast<double>(e.landing_brightness);
  d["seen_through_brightness"] = static_cast<double>(e.seenThroughBrightness());
  d["landing_fitness"] = static_cast<double>(e.landing_fitness);
  d["plane_refined"] = e.plane_refined;
  d["plane_correction"] = static_cast<double>(e.plane_correction);
  const core::IntensityFeatures& intensity = object.intensity;
  d["intensity_echoes"] = intensity.echoes;
  d["intensity_off_peak"] = intensity.off_peak;
  d["intensity_faint_share"] = static_cast<double>(intensity.faint_share);
  d["intensity_bright_off_peak"] = intensity.bright_off_peak;
  d["intensity_bright_backed_share"] = static_cast<double>(intensity.bright_backed_share);
  d["intensity_diffuse_reflector"] = intensity.diffuse_reflector;
  d["intensity_pane_by_echoes"] = intensity.pane_by_echoes;
  d["intensity_seen_through_pane"] = intensity.seen_through_pane;
  d["intensity_oblique_faint_surface"] = intensity.oblique_faint_surface;
  d["intensity_haze"] = static_cast<double>(intensity.haze);
  d["intensity_echo_ratio"] = static_cast<double>(intensity.echo_ratio);
  d["intensity_log_odds"] = static_cast<double>(intensity.log_odds);
  d["intensity_typed"] = intensity.typed;
  return d;
}

py::dict statsOf(const core::PipelineResult& r, const core::Params& params)
{
  py::dict stats;
  stats["range_gated_points"] = r.range_gated_points;
  stats["outlier_points"] = r.outlier_points;
  stats["error_surface_points"] = r.error_surface_points;
  stats["seconds"] = r.times.total;
  py::dict stage_seconds;
  stage_seconds["sampling"] = r.times.sampling;
  stage_seconds["range_gate"] = r.times.range_gate;
  stage_seconds["outlier_filter"] = r.times.outlier_filter;
  stage_seconds["echo_comparison"] = r.times.echo_comparison;
  stage_seconds["object_extraction"] = r.times.object_extraction;
  stage_seconds["type_analysis"] = r.times.type_analysis;
  stage_seconds["object_stages"] = r.times.object_stages;
  stage_seconds["cone_labelling"] = r.times.cone_labelling;
  stage_seconds["reflection_chains"] = r.times.reflection_chains;
  stage_seconds["cleaned_output"] = r.times.cleaned_output;
  stats["stage_seconds"] = stage_seconds;
  stats["released_surface_beams"] = r.released_surface_beams;
  stats["mixed_pixel_beams"] = r.mixed_pixel_beams;
  stats["specular_spot_points"] = r.specular_spot_points;
  stats["echo_separation"] = r.echo_separation;
  stats["multiply_reflected_phantoms"] = r.reflection_chains.multiply_reflected;
  stats["unexplained_phantoms"] = r.reflection_chains.unexplained;
  stats["merged_echoes"] = r.assignment.merged_echoes[0].size() + r.assignment.merged_echoes[1].size();
  // A stage that removed an implausible share of the sweep, in words (core/removal_report.h).
  py::list warnings;
  for (const std::string& warning : core::removalWarnings(r.removals, params))
    warnings.append(warning);
  stats["warnings"] = warnings;
  return stats;
}

Records cleanedArray(const std::vector<core::OutputPoint>& cleaned)
{
  Records out(static_cast<py::ssize_t>(cleaned.size()));
  core::writeCleanedRecords(cleaned, recordBytes(out));
  return out;
}

py::list objectList(const std::vector<core::ReflectiveObject>& objects)
{
  py::list list;
  for (const core::ReflectiveObject& object : objects)
    list.append(objectToDict(object));
  return list;
}

// A sweep's context from Python: no stamp or frame (the points are in the scanner's frame), and
// with `pose` (a 4 x 4 rigid transform, fixed_from_sweep) its place in the post-filter's fixed frame.
core::SweepContext contextWithPose(const py::object& pose)
{
  core::SweepContext context;
  if (pose.is_none())
    return context;
  const py::array_t<double, py::array::c_style | py::array::forcecast> matrix(pose);
  if (matrix.ndim() != 2 || matrix.shape(0) != 4 || matrix.shape(1) != 4)
    throw py::value_error("pose must be a 4 x 4 matrix (fixed_from_sweep), not of shape " +
                          std::string(py::str(py::object(pose.attr("shape")))));
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      m(r, c) = matrix.at(r, c);
  const Eigen::Matrix3d rotation = m.topLeftCorner<3, 3>();
  if (!m.allFinite() || !(rotation * rotation.transpose()).isIdentity(1e-6) || rotation.determinant() < 0.0 ||
      !m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)))
    throw py::value_error("pose must be a rigid transform: an orthonormal rotation (determinant 1), a "
                          "translation, last row [0, 0, 0, 1]");
  context.has_fixed_pose = true;
  context.fixed_from_sweep.matrix() = m;
  return context;
}

// The intensity features of a known rectangle in one sweep (sensor at the origin), computed by the
// core's intensity_evidence stage itself (intensityScale, intensityFeatures), so that
// scripts/calibrate_intensity fits the model on exactly what the stage measures.
py::dict intensityFeaturesOf(const py::object& echo1, const py::object& echo2, const py::object& intensity1,
                             const py::object& intensity2, const std::array<std::array<double, 3>, 4>& corners,
                             const std::array<double, 4>& plane, double plane_threshold, double echo_threshold)
{
  std::size_t rows1 = 0, cols1 = 0, rows2 = 0, cols2 = 0;
  const py::array points1 = checkPoints(echo1, "echo1", true, rows1, cols1);
  const py::array points2 = checkPoints(echo2, "echo2", true, rows2, cols2);
  if (rows1 * cols1 != rows2 * cols2)
    throw py::value_error("echo1 and echo2 must be index-aligned (the same number of points)");
  const std::size_t n = rows1 * cols1;
  const py::object intensities1 = checkIntensities(intensity1, "intensity1", n);
  const py::object intensities2 = checkIntensities(intensity2, "intensity2", n);
  const float* i1 = intensityData(intensities1);
  const float* i2 = intensityData(intensities2);
  if (i1 == nullptr || i2 == nullptr)
    throw py::value_error("intensity features need the intensities of both echoes");
  const Eigen::Vector3d normal(plane[0], plane[1], plane[2]);
  if (!(normal.norm() > 0.0))
    throw py::value_error("plane (a, b, c, d) needs a normal (a, b, c) that is not zero");

  core::Sweep sweep;
  sweep.resize(rows1, cols1);
  for (int k = 0; k < 2; ++k)
  {
    const std::int64_t bad = copyPoints(k == 0 ? points1 : points2, sweep.echoes[k].points);
    if (bad >= 0)
      throwPartlyFinite(k == 0 ? "echo1" : "echo2", bad, sweep.echoes[k].points[static_cast<std::size_t>(bad)]);
    copyIntensities(k == 0 ? i1 : i2, sweep.echoes[k].intensities);
  }
  sweep.has_intensity = true;
  sweep.computeRanges(Eigen::Vector3f::Zero());

  core::ReflectiveObject object;
  object.plane << (normal / normal.norm()).cast<float>(), static_cast<float>(plane[3] / normal.norm());
  const auto corner = [&](std::size_t k) { return Eigen::Vector3d(corners[k][0], corners[k][1], corners[k][2]); };
  const Eigen::Vector3d width = corner(1) - corner(0), height = corner(3) - corner(0);
  object.centre = (0.25 * (corner(0) + corner(1) + corner(2) + corner(3))).cast<float>();
  object.width = static_cast<float>(width.norm());
  object.height = static_cast<float>(height.norm());
  object.width_axis = width.normalized().cast<float>();
  object.height_axis = height.normalized().cast<float>();

  core::IntensityEvidenceConfig config;
  config.plane_threshold = static_cast<float>(plane_threshold);
  config.echo_threshold = static_cast<float>(echo_threshold);
  core::IntensityFeatures f;
  {
    py::gil_scoped_release release;
    f = core::intensityFeatures(sweep, Eigen::Vector3f::Zero(), object, core::intensityScale(sweep), config);
  }
  py::dict d;
  d["echoes"] = f.echoes;
  d["off_peak"] = f.off_peak;
  d["faint_share"] = static_cast<double>(f.faint_share);
  d["haze"] = static_cast<double>(f.haze);
  d["echo_ratio"] = static_cast<double>(f.echo_ratio);
  return d;
}

// The pipeline and its reused sweep. One call at a time per object (a mutex, taken with the
// GIL released so that other Python threads run meanwhile).
class PythonPipeline
{
public:
  explicit PythonPipeline(const core::Params& params) : pipeline_(params) {}

  // Every taker of mutex_ releases the GIL first: a filter call holding the mutex takes the GIL
  // back to build its outputs, so waiting for the mutex with the GIL held would deadlock.
  void setParams(const core::Params& params)
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    pipeline_.setParams(params);
  }
  core::Params params()
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    return pipeline_.params();
  }

  // Two index-aligned echoes (input modes pair / two_topics).
  py::tuple filterPair(const py::object& echo1, const py::object& echo2, const py::object& intensity1,
                       const py::object& intensity2, const py::object& pose)
  {
    const core::SweepContext context = contextWithPose(pose);
    std::size_t rows1 = 0, cols1 = 0, rows2 = 0, cols2 = 0;
    const py::array points1 = checkPoints(echo1, "echo1", true, rows1, cols1);
    const py::array points2 = checkPoints(echo2, "echo2", true, rows2, cols2);
    if (rows1 * cols1 != rows2 * cols2)
      throw py::value_error("echo1 has " + std::to_string(rows1 * cols1) + " points but echo2 has " +
                            std::to_string(rows2 * cols2) + "; the echoes must be index-aligned");
    const std::size_t n = rows1 * cols1;
    const py::object i1 = checkIntensities(intensity1, "intensity1", n);
    const py::object i2 = checkIntensities(intensity2, "intensity2", n);
    const float* i1_data = intensityData(i1);
    const float* i2_data = intensityData(i2);

    Records labelled(static_cast<py::ssize_t>(2 * n));
    std::uint8_t* records = recordBytes(labelled);
    Records cleaned;
    py::list objects;
    py::dict stats;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      std::int64_t bad[2];
      {
        sweep_.resize(rows1, cols1);
        sweep_.input_cells.clear();
        bad[0] = copyPoints(points1, sweep_.echoes[0].points);
        bad[1] = copyPoints(points2, sweep_.echoes[1].points);
        copyIntensities(i1_data, sweep_.echoes[0].intensities);
        copyIntensities(i2_data, sweep_.echoes[1].intensities);
        sweep_.has_intensity = i1_data != nullptr && i2_data != nullptr;
        sweep_.computeRanges(context.sensorOrigin());
      }
      for (int k = 0; k < 2; ++k)
        if (bad[k] >= 0)
        {
          py::gil_scoped_acquire acquire;
          throwPartlyFinite(k == 0 ? "echo1" : "echo2", bad[k], sweep_.echoes[k].points[static_cast<std::size_t>(bad[k])]);
        }
      const core::PipelineResult& r = pipeline_.process(sweep_, context);
      core::writeLabelledRecords(sweep_, r.labels, records);
      py::gil_scoped_acquire acquire;
      cleaned = cleanedArray(r.cleaned);
      objects = objectList(r.objects);
      stats = statsOf(r, pipeline_.params());
    }
    return py::make_tuple(labelled, cleaned, objects, stats);
  }

  // The post-filter's map objects in the fixed frame (normals towards `viewpoint`), each as an
  // object dict with sweeps_seen and mirror_log_odds.
  py::list mapObjects(const std::array<double, 3>& viewpoint)
  {
    std::vector<core::ReflectiveObject> objects;
    std::vector<std::pair<std::uint32_t, double>> evidence;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      const core::ObjectMap& map = pipeline_.objectMap();
      const Eigen::Vector3f from(static_cast<float>(viewpoint[0]), static_cast<float>(viewpoint[1]),
                                 static_cast<float>(viewpoint[2]));
      for (const core::MapObject& object : map.objects())
      {
        objects.push_back(map.toReflectiveObject(object, Eigen::Isometry3d::Identity(), from));
        evidence.emplace_back(object.sweeps_seen, object.mirror_log_odds);
      }
    }
    py::list list = objectList(objects);
    for (std::size_t k = 0; k < objects.size(); ++k)
    {
      py::dict d = list[k];
      d["sweeps_seen"] = evidence[k].first;
      d["mirror_log_odds"] = evidence[k].second;
    }
    return list;
  }

  // The map as a YAML file (core/object_map_file.h): "" or what went wrong.
  std::string saveMap(const std::string& path, const std::string& fixed_frame)
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    return core::saveObjectMap(path, fixed_frame, pipeline_.objectMap());
  }
  std::string loadMap(const std::string& path, const std::string& fixed_frame)
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    return core::loadObjectMap(path, fixed_frame, pipeline_.objectMap());
  }

  // One cloud holding both returns (input mode dual_return); labelled keeps the input's order.
  py::tuple filterDualReturn(const py::object& points_object, const py::object& returns_object,
                             const py::object& rings_object, const py::object& intensities_object,
                             double azimuth_resolution_deg, const py::object& pose)
  {
    const core::SweepContext context = contextWithPose(pose);
    const std::string resolution_problem = core::validateAzimuthResolution(azimuth_resolution_deg);
    if (!resolution_problem.empty())
      throw py::value_error(resolution_problem);
    std::size_t rows = 0, n = 0;
    const py::array points = checkPoints(points_object, "points", false, rows, n);
    const auto returns = checkIntegers(returns_object, "returns", n);
    const auto rings = checkIntegers(rings_object, "rings", n);
    const py::object intensities = checkIntensities(intensities_object, "intensities", n);
    const float* intensity_data = intensityData(intensities);
    const std::int64_t* returns_data = returns.data();
    const std::int64_t* rings_data = rings.data();

    Records labelled(static_cast<py::ssize_t>(n));
    std::uint8_t* records = recordBytes(labelled);
    Records cleaned;
    py::list objects;
    py::dict stats;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      input_.points.points.resize(n);
      input_.points.intensities.resize(n);
      const std::int64_t bad = copyPoints(points, input_.points.points);
      if (bad >= 0)
      {
        py::gil_scoped_acquire acquire;
        throwPartlyFinite("points", bad, input_.points.points[static_cast<std::size_t>(bad)]);
      }
      copyIntensities(intensity_data, input_.points.intensities);
      input_.has_intensity = intensity_data != nullptr;
      input_.returns.assign(returns_data, returns_data + n);
      input_.rings.assign(rings_data, rings_data + n);
      const core::DualReturnStats binning = binner_.bin(input_, azimuth_resolution_deg, sweep_);
      const core::PipelineResult& r = pipeline_.process(sweep_, context);
      // The input's order and count; points in no grid cell are nanPoint, echo 0.
      core::writeLabelledRecords(sweep_, r.labels, records);
      py::gil_scoped_acquire acquire;
      cleaned = cleanedArray(r.cleaned);
      objects = objectList(r.objects);
      stats = statsOf(r, pipeline_.params());
      stats["rows"] = sweep_.rows;
      stats["cols"] = sweep_.cols;
      stats["return_base"] = binning.return_base;
      stats["binned_points"] = binning.binned;
      stats["paired_beams"] = binning.paired_beams;
      stats["single_beams"] = binning.single_beams;
      stats["unbinned_points"] = binning.unbinned();
      stats["azimuth_resolution_deg"] = binning.azimuth_resolution_deg;
      stats["azimuth_from_cloud"] = binning.azimuth_from_cloud;
      // Points binning could not place, in the same words as the node's warning: without it a
      // Python user lost them silently (a fifth of an Ouster frame once, on a too-coarse step).
      const std::string unbinned = core::describeUnbinned(binning);
      if (!unbinned.empty())
      {
        py::list warnings = stats["warnings"];
        warnings.append("dual_return: " + unbinned);
      }
    }
    return py::make_tuple(labelled, cleaned, objects, stats);
  }

private:
  std::mutex mutex_;
  core::Pipeline pipeline_;
  core::Sweep sweep_;
  core::DualReturnInput input_;
  core::DualReturnBinner binner_;
};
}  // namespace

PYBIND11_MODULE(_core, m)
{
  m.doc() = "The ROS-free pre-filter core on numpy arrays; use ohm_mirror_detector3d.core instead.";

  PYBIND11_NUMPY_DTYPE(core::OutputRecord, x, y, z, intensity, label, echo, beam);

  py::class_<core::Params> params(m, "Params", "The core's parameters under their C++ names (core/params.h).");
  params.def(py::init<>());
  for (const core::ParamInfo& param : core::parameterTable())
  {
    if (param.real_field != nullptr)
      params.def_readwrite(param.field, param.real_field);
    else if (param.integer_field != nullptr)
      params.def_readwrite(param.field, param.integer_field);
  }
  params.def("validate", &core::Params::validate, "One message per bad value; empty when all are acceptable.");
  m.def("parameter_table", &parameterTable, "Every parameter (core/param_table.h) as a dict, in the table's order.");
  m.def("check_start_up", &checkStartUp, py::arg("name"), py::arg("value"),
        "Empty when value is usable for the start-up parameter, otherwise why not (its core check).");
  m.def(
      "map_legacy_values",
      [](core::Params params, const std::vector<std::string>& given) {
        const std::vector<std::string> lines = core::mapLegacyValues(
            [&](const std::string& name) { return std::find(given.begin(), given.end(), name) != given.end(); },
            params);
        return py::make_tuple(params, lines);
      },
      py::arg("params"), py::arg("given_names"),
      "(params, lines): the original's values given under its names alone mapped to what they meant, "
      "one line per mapped parameter (core/legacy_values.h).");

  m.def("intensity_features", &intensityFeaturesOf, py::arg("echo1"), py::arg("echo2"), py::arg("intensity1"),
        py::arg("intensity2"), py::arg("corners"), py::arg("plane"), py::arg("plane_threshold"),
        py::arg("echo_threshold"),
        "{echoes, off_peak, faint_share, haze, echo_ratio} of a known rectangle (corners in order around it, "
        "plane a b c d) in one sweep with the sensor at the origin: the intensity_evidence stage's own code.");

  py::class_<PythonPipeline>(m, "Pipeline")
      .def(py::init<const core::Params&>(), py::arg("params"))
      .def("set_params", &PythonPipeline::setParams, py::arg("params"))
      .def_property_readonly("params", &PythonPipeline::params)
      .def("filter_pair", &PythonPipeline::filterPair, py::arg("echo1"), py::arg("echo2"),
           py::arg("intensity1") = py::none(), py::arg("intensity2") = py::none(), py::arg("pose") = py::none(),
           "(labelled, cleaned, objects, stats) of two index-aligned echoes; pose: fixed_from_sweep (4 x 4) "
           "for the post-filter.")
      .def("filter_dual_return", &PythonPipeline::filterDualReturn, py::arg("points"), py::arg("returns"),
           py::arg("rings"), py::arg("intensities") = py::none(),
           py::arg("azimuth_resolution_deg") = core::kAzimuthStepFromCloud, py::arg("pose") = py::none(),
           "(labelled, cleaned, objects, stats) of one cloud holding both returns; pose as filter_pair.")
      .def("map_objects", &PythonPipeline::mapObjects, py::arg("viewpoint"),
           "The post-filter's map objects in the fixed frame (object dicts with sweeps_seen, mirror_log_odds).")
      .def("save_map", &PythonPipeline::saveMap, py::arg("path"), py::arg("fixed_frame"),
           "Writes the object map as YAML; '' or the problem.")
      .def("load_map", &PythonPipeline::loadMap, py::arg("path"), py::arg("fixed_frame"),
           "Replaces the object map by a file's; '' or the problem (the map is then empty).");

  m.attr("OUTPUT_DTYPE") = py::dtype::of<core::OutputRecord>();
}
