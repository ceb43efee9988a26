// `make bench`, nodelet latency with the driver in the same nodelet manager: this program is itself
// the manager. It loads ohm_mirror_detector3d/PreFilterNodelet with nodelet::Loader into its own
// process (parameters from a flat YAML file such as launch/rotating_hokuyo_params.yaml, set on the
// nodelet's private namespace before loading), then publishes the EchoPair read from a bag as a
// ConstPtr, as a driver nodelet in the same manager would. roscpp hands such messages to in-process
// subscribers by pointer, so neither the input nor `cleaned` is serialised: what remains outside the
// core is the conversion to a Sweep, the conversion to PointCloud2 and the publish calls.
//
// Usage (needs a master; bench/nodelet_latency.py --inprocess starts one):
//   nodelet_latency_inprocess --bag BAG --params YAML [--sweeps N] [--warmup W]
// The bag's first EchoPair message is the sweep; every run gets a fresh copy (made before the stamp
// is taken, so the copy is not timed) with header.stamp = ros::Time::now() just before publish.
// Prints one JSON line: medians of core (the nodelet's own timing of core::Pipeline::process),
// input stamp -> `cleaned` published (from the nodelet's ~timing topic), input stamp -> `cleaned`
// received here (a ConstPtr subscriber), and the ratio published / core.
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nodelet/loader.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Float64MultiArray.h>

#include "ohm_mirror_detector3d/EchoPair.h"
#include "ohm_mirror_detector3d/ros/yaml_params.h"

namespace ohm = ohm_mirror_detector3d;

namespace
{
const char* const kNodeletName = "/prefilter";

double median(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double percentile95(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<std::size_t>(0.95 * (values.size() - 1) + 0.5))];
}

// Every name of the file onto the parameter server under the nodelet's private namespace, typed as
// `rosparam load` would type it (integer, number, boolean, list of numbers, else string).
void setParams(const std::string& path)
{
  ohm::ros_io::YamlParamFile file(path);
  for (const std::string& name : file.unusedNames())  // nothing asked yet: every name, in file order
  {
    const std::string key = std::string(kNodeletName) + "/" + name;
    int integer = 0;
    double number = 0.0;
    std::string text;
    std::vector<double> list;
    if (file.get(name, integer))
      ros::param::set(key, integer);
    else if (file.get(name, number))
      ros::param::set(key, number);
    else if (file.get(name, list))
      ros::param::set(key, list);
    else if (file.get(name, text))
    {
      if (text == "true" || text == "false")
        ros::param::set(key, text == "true");
      else
        ros::param::set(key, text);
    }
    else
      throw std::runtime_error("cannot set parameter '" + name + "' of " + path);
  }
}

ohm::EchoPair::ConstPtr readPair(const std::string& path)
{
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  for (const rosbag::MessageInstance& instance : view)
  {
    ohm::EchoPair::ConstPtr pair = instance.instantiate<ohm::EchoPair>();
    if (pair)
      return pair;
  }
  throw std::runtime_error("no EchoPair message in " + path);
}
}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "nodelet_latency_inprocess", ros::init_options::AnonymousName);
  std::string bag_path;
  std::string params_path;
  int sweeps = 30;
  int warmup = 3;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (i + 1 >= argc)
    {
      std::fprintf(stderr, "missing value after %s\n", arg.c_str());
      return 2;
    }
    if (arg == "--bag")
      bag_path = argv[++i];
    else if (arg == "--params")
      params_path = argv[++i];
    else if (arg == "--sweeps")
      sweeps = std::atoi(argv[++i]);
    else if (arg == "--warmup")
      warmup = std::atoi(argv[++i]);
    else
    {
      std::fprintf(stderr, "unknown argument %s\n", arg.c_str());
      return 2;
    }
  }
  if (bag_path.empty() || params_path.empty() || sweeps < 1 || warmup < 0)
  {
    std::fprintf(stderr, "usage: %s --bag BAG --params YAML [--sweeps N >= 1] [--warmup W]\n", argv[0]);
    return 2;
  }

  ros::NodeHandle nh;
  const ohm::EchoPair::ConstPtr original = readPair(bag_path);
  setParams(params_path);

  // The manager's side: the nodelet runs on the Loader's own worker threads, as in a nodelet
  // manager; no load/unload services are needed here.
  nodelet::Loader loader(false);
  if (!loader.load(kNodeletName, "ohm_mirror_detector3d/PreFilterNodelet", nodelet::M_string(), nodelet::V_string()))
  {
    std::fprintf(stderr, "could not load ohm_mirror_detector3d/PreFilterNodelet (workspace sourced?)\n");
    return 1;
  }

  std::mutex mutex;
  std::condition_variable changed;
  std::map<ros::Time, double> received;  // stamp -> seconds from the input stamp to reception
  std::vector<std::pair<double, double>> timings;  // (core, stamp -> cleaned published), seconds

  const std::string ns = kNodeletName;
  ros::Subscriber cleaned_sub = nh.subscribe<sensor_msgs::PointCloud2>(
      ns + "/cleaned", 5, [&](const sensor_msgs::PointCloud2::ConstPtr& cloud) {
        const double age = (ros::Time::now() - cloud->header.stamp).toSec();
        std::lock_guard<std::mutex> lock(mutex);
        received[cloud->header.stamp] = age;
        changed.notify_all();
      });
  ros::Subscriber timing_sub = nh.subscribe<std_msgs::Float64MultiArray>(
      ns + "/timing", 50, [&](const std_msgs::Float64MultiArray::ConstPtr& timing) {
        if (timing->data.size() < 2)
          return;
        std::lock_guard<std::mutex> lock(mutex);
        timings.emplace_back(timing->data[0], timing->data[1]);
        changed.notify_all();
      });
  ros::Publisher input_pub = nh.advertise<ohm::EchoPair>(ns + "/input", 1);
  ros::AsyncSpinner spinner(1);  // this program's callbacks; the nodelet has its own threads
  spinner.start();

  // The nodelet subscribes to its input once an output has a subscriber.
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && (input_pub.getNumSubscribers() == 0 || timing_sub.getNumPublishers() == 0 ||
                       cleaned_sub.getNumPublishers() == 0))
  {
    if (ros::WallTime::now() > give_up)
    {
      std::fprintf(stderr, "the nodelet did not connect to %s/input, cleaned and timing within 30 s\n", ns.c_str());
      return 1;
    }
    ros::WallDuration(0.05).sleep();
  }
  ros::WallDuration(0.5).sleep();

  std::vector<double> core;
  std::vector<double> published;
  std::vector<double> latency;
  for (int i = 0; i < warmup + sweeps; ++i)
  {
    ohm::EchoPair::Ptr pair(new ohm::EchoPair(*original));  // outside the timed span
    std::size_t before = 0;
    {
      std::lock_guard<std::mutex> lock(mutex);
      before = timings.size();
    }
    pair->header.stamp = ros::Time::now();
    pair->echo1.header.stamp = pair->echo2.header.stamp = pair->header.stamp;
    const ros::Time stamp = pair->header.stamp;
    input_pub.publish(ohm::EchoPair::ConstPtr(pair));
    pair.reset();  // the nodelet holds the only reference now
    std::unique_lock<std::mutex> lock(mutex);
    if (!changed.wait_for(lock, std::chrono::seconds(30),
                          [&] { return received.count(stamp) && timings.size() > before; }))
    {
      std::fprintf(stderr, "no cleaned/timing answer from the nodelet for sweep %d\n", i);
      return 1;
    }
    if (i >= warmup)
    {
      core.push_back(timings[before].first);
      published.push_back(timings[before].second);
      latency.push_back(received[stamp]);
    }
    lock.unlock();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  spinner.stop();
  loader.clear();

  const double core_ms = 1e3 * median(core);
  const double published_ms = 1e3 * median(published);
  const std::size_t beams = static_cast<std::size_t>(original->echo1.width) * original->echo1.height;
  std::printf("{\"beams\": %zu, \"rows\": %u, \"cols\": %u, \"sweeps\": %d, \"core_ms\": %.2f, "
              "\"in_nodelet_ms\": %.2f, \"ratio\": %.3f, \"received_ms\": %.2f, \"in_nodelet_p95_ms\": %.2f}\n",
              beams, original->echo1.height, original->echo1.width, sweeps, core_ms, published_ms,
              published_ms / core_ms, 1e3 * median(latency), 1e3 * percentile95(published));
  return 0;
}
