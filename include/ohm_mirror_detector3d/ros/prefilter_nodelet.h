// The pre-filter as a nodelet: converts messages, runs core::Pipeline, publishes.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <message_filters/subscriber.h>
#include <message_filters/time_synchronizer.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <sensor_msgs/MultiEchoLaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <topic_tools/shape_shifter.h>

#include <boost/thread/recursive_mutex.hpp>
#include <memory>
#include <mutex>
#include <string>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/PreFilterConfig.h"
#include "ohm_mirror_detector3d/core/dual_return.h"
#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/message_pipeline.h"
#include "ohm_mirror_detector3d/ros/multi_echo_scan.h"
#include "ohm_mirror_detector3d/ros/processing_stats.h"
#include "ohm_mirror_detector3d/ros/problem_throttle.h"

namespace ohm_mirror_detector3d
{
class PreFilterNodelet : public nodelet::Nodelet
{
private:
  using EchoSync = message_filters::TimeSynchronizer<sensor_msgs::PointCloud2, sensor_msgs::PointCloud2>;

  void onInit() override;
  void advertiseOutputs();
  // /diagnostics every ~diagnostic_period seconds (default 1): see ProcessingStats.
  void startDiagnostics();

  // Lazy subscription: the input is subscribed only while an output has a subscriber.
  void updateSubscription();
  void subscribe();
  void unsubscribe();

  void onEchoPair(const EchoPair::ConstPtr& pair);
  void onEchoClouds(const sensor_msgs::PointCloud2::ConstPtr& echo1, const sensor_msgs::PointCloud2::ConstPtr& echo2);
  // multi_echo_scan: queues a scan (null: only drains the queue, from the timer) and runs
  // the pipeline on every sweep it completes.
  void onMultiEchoScan(const sensor_msgs::MultiEchoLaserScan::ConstPtr& scan);
  void onDualReturnCloud(const sensor_msgs::PointCloud2::ConstPtr& cloud);
  void onLegacyMessage(const topic_tools::ShapeShifter::ConstPtr& message);
  void onReconfigure(PreFilterConfig& config, std::uint32_t level);
  // Runs the pipeline on the sweep in pipeline_ with `context` (the sensor at the origin of the
  // header's frame when none is given) and publishes what is subscribed.
  void processAndPublish(const std_msgs::Header& header);
  void processAndPublish(const std_msgs::Header& header, core::SweepContext context);
  // sensor_frame: puts the scanner's pose in the cloud's frame into the context (the vision
  // cones start there) and measures the sweep's ranges from it. False, with a throttled error,
  // when tf cannot say.
  bool placeSensor(const std_msgs::Header& header, core::SweepContext& context);
  // Logs a problem with the input on `topic` ("dropping sweep on TOPIC: PROBLEM" as an error,
  // or "sweep on TOPIC: PROBLEM" as a warning), throttled per kind of problem.
  void reportInputProblem(bool dropped, const std::string& what, const std::string& topic,
                          const std::string& problem);

  std::string input_mode_;
  std::string input_topic_;  // pair mode
  double azimuth_resolution_deg_ = core::kDefaultAzimuthResolutionDeg;  // dual_return mode

  ros::Publisher labelled_pub_;
  ros::Publisher cleaned_pub_;
  ros::Publisher objects_pub_;
  ros::Publisher markers_pub_;
  ros::Publisher timing_pub_;  // ~timing, for make bench: see processAndPublish

  std::mutex subscription_mutex_;
  bool subscribed_ = false;
  ros::Subscriber pair_sub_;
  message_filters::Subscriber<sensor_msgs::PointCloud2> echo1_sub_;
  message_filters::Subscriber<sensor_msgs::PointCloud2> echo2_sub_;
  std::unique_ptr<EchoSync> echo_sync_;
  // multi_echo_scan: the scan queue, tf and the sweep assembler; a timer retries the scans
  // that wait for their transforms.
  std::unique_ptr<ros_io::MultiEchoScanInput> scan_input_;
  ros::Subscriber scan_sub_;
  ros::WallTimer scan_drain_timer_;
  // Optional: the scanner's frame when the clouds come in another frame; tf supplies it.
  std::string sensor_frame_;
  std::unique_ptr<tf2_ros::Buffer> sensor_tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> sensor_tf_listener_;

  ros::Subscriber dual_return_sub_;
  ros::Subscriber legacy_sub_;

  // Guards the pipeline and its sweep buffer: reconfigure runs on another thread than
  // the input callbacks.
  std::mutex pipeline_mutex_;
  ros_io::MessagePipeline pipeline_;
  core::DualReturnInput dual_return_input_;  // buffer of the dual_return adapter
  ros_io::Hokuyo3dLegacyDecoder legacy_decoder_;  // hokuyo3d_legacy: cached definition
  std::vector<std::uint8_t> legacy_bytes_;

  std::mutex problem_mutex_;
  ros_io::ProblemThrottle problem_throttle_{ 5.0 };

  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<PreFilterConfig>> reconfigure_server_;
  PreFilterConfig active_config_;

  ros_io::ProcessingStats stats_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_;
};

}  // namespace ohm_mirror_detector3d
