// The pre-filter as a nodelet: subscribes to the input mode's topics, converts through the
// input-mode table (SweepInput), runs MessagePipeline, publishes.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <sensor_msgs/PointCloud2.h>

#include <boost/thread/recursive_mutex.hpp>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/MapFile.h"
#include "ohm_mirror_detector3d/PreFilterConfig.h"
#include "ohm_mirror_detector3d/ros/input_mode.h"
#include "ohm_mirror_detector3d/ros/legacy_outputs.h"
#include "ohm_mirror_detector3d/ros/message_pipeline.h"
#include "ohm_mirror_detector3d/ros/parameters.h"
#include "ohm_mirror_detector3d/ros/processing_stats.h"
#include "ohm_mirror_detector3d/ros/problem_throttle.h"
#include "ohm_mirror_detector3d/ros/sweep_input.h"

namespace ohm_mirror_detector3d
{
class PreFilterNodelet : public nodelet::Nodelet, private ros_io::SweepReceiver
{
private:
  void onInit() override;
  // Reads the output topics' names from `source` (appending a message per bad one to `errors`).
  void advertiseOutputs(const ros_io::ParamSource& source, bool every_legacy_output, std::vector<std::string>& errors);
  // /diagnostics every ~diagnostic_period seconds (default 1): see ProcessingStats.
  void startDiagnostics();
  // A publisher of another type on a typed input topic: roscpp refuses the connection and nothing
  // arrives, so the master's record of the topic's type is checked while the input is subscribed.
  void checkInputPublishers();

  // Lazy subscription: the input is subscribed only while an output has a subscriber.
  void updateSubscription();
  void subscribe();
  void unsubscribe();

  void onReconfigure(PreFilterConfig& config, std::uint32_t level);
  // ~save_map / ~load_map (the post-filter's object map as YAML; an empty path: map_file).
  bool onSaveMap(MapFile::Request& request, MapFile::Response& response);
  bool onLoadMap(MapFile::Request& request, MapFile::Response& response);
  // SweepReceiver: a sweep from the input (after its transform, with sensor_frame) goes through
  // the pipeline and out; a problem is logged (throttled) and counted.
  void sweepReady(core::Sweep& sweep, const core::SweepContext& context) override;
  void inputProblem(const ros_io::InputProblem& problem) override;
  // Logs which mode reads the input (input_mode not set), and hands the driver's definition to
  // the outputs in the original's types (hokuyo3d_legacy).
  void inputTypeFound(const ros_io::FoundInputType& type) override;
  void processAndPublish(const core::SweepContext& context);
  // Logs a problem with the input ("dropping WHAT on TOPIC: PROBLEM" as an error, or "WHAT on
  // TOPIC: PROBLEM" as a warning), throttled per kind of problem.
  void reportInputProblem(const ros_io::InputProblem& problem);

  ros::Publisher labelled_pub_;
  ros::Publisher cleaned_pub_;
  ros::Publisher objects_pub_;
  ros::Publisher markers_pub_;
  ros::Publisher timing_pub_;  // ~timing, for make bench: see processAndPublish
  // The post-filter's object map in fixed_frame_: ~map_objects, ~map_markers, ~map_evidence.
  ros::Publisher map_objects_pub_;
  ros::Publisher map_markers_pub_;
  ros::Publisher map_evidence_pub_;
  ros::ServiceServer save_map_service_;
  ros::ServiceServer load_map_service_;
  std::string fixed_frame_;
  std::string map_file_;
  // The original's outputs (pub_scan, pub_cleaned, ...) that are set, or all in hokuyo3d_legacy.
  ros_io::LegacyPublishers legacy_;

  // Transforms for multi_echo_scan and sensor_frame: filled by a listener on a thread of its own,
  // so that they keep coming while the pipeline runs; never waited for in a callback.
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;

  // The input mode's adapter (and the wait for sensor_frame's transform).
  std::unique_ptr<ros_io::SweepInput> input_;
  std::mutex subscription_mutex_;  // guards subscribed_, input_subscribers_, poll_timer_
  bool subscribed_ = false;

  // Guards the pipeline: reconfigure runs on another thread than the input callbacks.
  std::mutex pipeline_mutex_;
  ros_io::MessagePipeline pipeline_;

  std::mutex problem_mutex_;  // guards problem_throttle_, found_type_
  ros_io::ProblemThrottle problem_throttle_{ 5.0 };
  ros_io::FoundInputType found_type_;  // the last one logged

  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<PreFilterConfig>> reconfigure_server_;
  PreFilterConfig active_config_;

  ros_io::ProcessingStats stats_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_;

  // Last, so that they go first: no callback runs into what is destroyed after them.
  std::vector<ros::Subscriber> input_subscribers_;
  // Hands on what waits for transforms that have come since (only when tf is used).
  ros::WallTimer poll_timer_;
  ros::WallTimer publisher_check_timer_;  // checkInputPublishers, while subscribed
};

}  // namespace ohm_mirror_detector3d
