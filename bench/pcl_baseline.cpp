#include "pcl_baseline.h"

#include <pcl/ModelCoefficients.h>
#include <pcl/console/print.h>
#include <pcl/filters/extract_indices.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <chrono>
#include <cmath>
#include <vector>

namespace core = ohm_mirror_detector3d::core;

namespace
{
using Clock = std::chrono::steady_clock;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;
// pcl::Indices from PCL 1.11 on, std::vector<int> in PCL 1.10 (ROS Noetic).
using IndexVector = decltype(pcl::PointIndices::indices);

double lap(Clock::time_point& start)
{
  const Clock::time_point now = Clock::now();
  const double seconds = std::chrono::duration<double>(now - start).count();
  start = now;
  return seconds;
}
}  // namespace

BaselineTimes runPclBaseline(const core::Sweep& sweep, const Eigen::Vector3f& sensor_origin, const core::Params& params)
{
  BaselineTimes times;
  // PCL's ICP reports a plane with too few correspondences (the glass) as an error on every
  // run; the baseline only needs the time.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  const Clock::time_point begin = Clock::now();
  Clock::time_point t = begin;
  const std::size_t beams = sweep.beamCount();

  // Range gate + outlier filter: every in-range point of both echoes in one cloud, filtered
  // by a kd-tree radius search per point.
  Cloud::Ptr all(new Cloud);
  std::vector<int> beam_of;  // beam * 2 + echo of each point of `all`
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < beams; ++i)
    {
      const float r = sweep.echoes[k].ranges[i];
      if (!(r >= params.min_range && r <= params.max_range))
        continue;
      const Eigen::Vector3f& p = sweep.echoes[k].points[i];
      all->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
      beam_of.push_back(static_cast<int>(2 * i + k));
    }
  pcl::RadiusOutlierRemoval<pcl::PointXYZ> outliers;
  outliers.setInputCloud(all);
  outliers.setRadiusSearch(params.outlier_radius);
  outliers.setMinNeighborsInRadius(params.outlier_min_neighbors);
  IndexVector kept;
  outliers.filter(kept);
  times.outlier_filter = lap(t);

  // Echo comparison on the surviving points.
  std::vector<char> alive(2 * beams, 0);
  for (int index : kept)
    alive[static_cast<std::size_t>(beam_of[static_cast<std::size_t>(index)])] = 1;
  Cloud::Ptr candidates(new Cloud);
  std::vector<std::size_t> candidate_beam;
  for (std::size_t i = 0; i < beams; ++i)
  {
    if (!alive[2 * i] || !alive[2 * i + 1])
      continue;
    const float r1 = sweep.echoes[0].ranges[i], r2 = sweep.echoes[1].ranges[i];
    if (!(std::fabs(r1 - r2) > params.echo_threshold))
      continue;
    const Eigen::Vector3f& p = sweep.echoes[r1 < r2 ? 0 : 1].points[i];
    candidates->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
    candidate_beam.push_back(i);
  }
  times.echo_comparison = lap(t);

  // Planes: RANSAC on all remaining candidates, one plane after another.
  std::vector<Eigen::Vector4f> planes;
  std::vector<Eigen::AlignedBox3f> extents;  // of each plane's inliers, grown by the cone margin
  pcl::SACSegmentation<pcl::PointXYZ> segmentation;
  segmentation.setModelType(pcl::SACMODEL_PLANE);
  segmentation.setMethodType(pcl::SAC_RANSAC);
  segmentation.setDistanceThreshold(params.plane_threshold);
  segmentation.setMaxIterations(1000);
  pcl::ExtractIndices<pcl::PointXYZ> extract;
  while (candidates->size() >= static_cast<std::size_t>(params.min_object_points))
  {
    pcl::PointIndices::Ptr inliers(new pcl::PointIndices);
    pcl::ModelCoefficients coefficients;
    segmentation.setInputCloud(candidates);
    segmentation.segment(*inliers, coefficients);
    if (inliers->indices.size() < static_cast<std::size_t>(params.min_object_points))
      break;
    Eigen::Vector4f plane(coefficients.values[0], coefficients.values[1], coefficients.values[2],
                          coefficients.values[3]);
    if (plane.head<3>().dot(sensor_origin) + plane[3] < 0.0f)
      plane = -plane;  // normal towards the sensor
    planes.push_back(plane);
    Eigen::AlignedBox3f extent;
    for (int index : inliers->indices)
      extent.extend(candidates->points[static_cast<std::size_t>(index)].getVector3fMap());
    extent.min().array() -= static_cast<float>(params.vision_cone_margin + params.plane_threshold);
    extent.max().array() += static_cast<float>(params.vision_cone_margin + params.plane_threshold);
    extents.push_back(extent);
    Cloud::Ptr rest(new Cloud);
    extract.setInputCloud(candidates);
    extract.setIndices(inliers);
    extract.setNegative(true);
    extract.filter(*rest);
    candidates = rest;
  }
  times.planes = lap(t);
  times.planes_found = planes.size();

  // Type: the points behind each plane seen through its inliers' extent, mirrored across it,
  // registered by ICP against every surviving point in front of the plane.
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  icp.setMaxCorrespondenceDistance(params.icp_max_distance);
  icp.setMaximumIterations(30);
  icp.setTransformationEpsilon(1e-9);
  for (std::size_t j = 0; j < planes.size(); ++j)
  {
    const Eigen::Vector4f& plane = planes[j];
    const float origin_side = plane.head<3>().dot(sensor_origin) + plane[3];
    Cloud::Ptr source(new Cloud), target(new Cloud);
    for (int index : kept)
    {
      const pcl::PointXYZ& q = all->points[static_cast<std::size_t>(index)];
      const Eigen::Vector3f p = q.getVector3fMap();
      const float side = plane.head<3>().dot(p) + plane[3];
      if (side > params.plane_threshold)
        target->push_back(q);
      else if (side < -params.plane_threshold)
      {
        const Eigen::Vector3f crossing =
            sensor_origin + (origin_side / (origin_side - side)) * (p - sensor_origin);
        if (!extents[j].contains(crossing))
          continue;
        const Eigen::Vector3f m = p - 2.0f * side * plane.head<3>();
        source->push_back(pcl::PointXYZ(m.x(), m.y(), m.z()));
      }
    }
    if (source->size() < 3 || target->size() < 3)
      continue;
    icp.setInputSource(source);
    icp.setInputTarget(target);
    Cloud aligned;
    icp.align(aligned);
  }
  times.icp = lap(t);
  times.total = std::chrono::duration<double>(t - begin).count();
  return times;
}
