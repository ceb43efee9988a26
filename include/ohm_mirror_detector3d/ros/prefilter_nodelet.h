// The pre-filter as a nodelet: converts messages, runs core::Pipeline, publishes.
#pragma once

#include <dynamic_reconfigure/server.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include <boost/thread/recursive_mutex.hpp>
#include <memory>
#include <mutex>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/PreFilterConfig.h"
#include "ohm_mirror_detector3d/core/pipeline.h"

namespace ohm_mirror_detector3d
{
class PreFilterNodelet : public nodelet::Nodelet
{
public:
  // Input modes this build understands (parameter `input_mode`).
  static constexpr const char* kInputModePair = "pair";

private:
  void onInit() override;

  // Lazy subscription: the input is subscribed only while an output has a subscriber.
  void updateSubscription();
  void onEchoPair(const EchoPair::ConstPtr& pair);
  void onReconfigure(PreFilterConfig& config, std::uint32_t level);
  void processAndPublish(const std_msgs::Header& header);

  ros::Publisher labelled_pub_;
  ros::Publisher cleaned_pub_;
  ros::Subscriber input_sub_;
  std::mutex subscription_mutex_;

  // Guards the pipeline and the sweep buffer: reconfigure runs on another thread than
  // the input callback.
  std::mutex pipeline_mutex_;
  core::Pipeline pipeline_;
  core::Sweep sweep_;

  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<PreFilterConfig>> reconfigure_server_;
  PreFilterConfig active_config_;
};

}  // namespace ohm_mirror_detector3d
