// Test node of legacy_output.test: publishes through the writers of the original's output
// types (legacy_output.h), as the nodelet will.
//   ~builtin_points  ohm_hokuyo3d/CoordDist of the built-in definition: the points of the
//                    parameter ~points (x y z intensity per point), frame "laser", at 5 Hz
//   ~scan, ~points   once a message arrives on ~driver (the original driver's
//                    CoordDistMulti, any definition): that sweep again as CoordDistMulti and
//                    its echo-1 returns as CoordDist, both in the driver connection's
//                    definition, advertised when the first driver message has given it
#include <ros/ros.h>
#include <topic_tools/shape_shifter.h>

#include <vector>

#include "ohm_mirror_detector3d/ros/hokuyo3d_legacy.h"
#include "ohm_mirror_detector3d/ros/legacy_output.h"

namespace
{
using ohm_mirror_detector3d::core::OutputPoint;
namespace ros_io = ohm_mirror_detector3d::ros_io;

class LegacyOutputPublisher
{
public:
  explicit LegacyOutputPublisher(ros::NodeHandle& pnh) : pnh_(pnh)
  {
    std::vector<double> values;
    pnh.getParam("points", values);
    if (values.size() % 4 != 0)
      throw std::invalid_argument("~points needs x y z intensity per point");
    for (std::size_t i = 0; i + 3 < values.size(); i += 4)
    {
      OutputPoint point{};
      point.position = Eigen::Vector3d(values[i], values[i + 1], values[i + 2]).cast<float>();
      point.intensity = static_cast<float>(values[i + 3]);
      builtin_points_.push_back(point);
    }
    builtin_pub_ = ros_io::advertise(pnh, builtin_writer_.type(), "builtin_points", 1);
    timer_ = pnh.createWallTimer(ros::WallDuration(0.2), [this](const ros::WallTimerEvent&) { publishBuiltin(); });
    driver_sub_ = pnh.subscribe<topic_tools::ShapeShifter>(
        "driver", 2, [this](const topic_tools::ShapeShifter::ConstPtr& message) { onDriver(*message); });
  }

private:
  void publishBuiltin()
  {
    std_msgs::Header header;
    header.stamp = ros::Time::now();
    header.frame_id = "laser";
    builtin_pub_.publish(builtin_writer_.write(header, builtin_points_));
  }

  void onDriver(const topic_tools::ShapeShifter& message)
  {
    std::vector<std::uint8_t> bytes(message.size());
    ros::serialization::OStream stream(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
    message.write(stream);
    std_msgs::Header header;
    std::string problem = decoder_.decode(message.getDataType(), message.getMessageDefinition(), bytes.data(),
                                          bytes.size(), sweep_, header);
    if (problem.empty() && !scan_pub_)
    {
      problem = scan_writer_.useDefinition(message.getDataType(), message.getMessageDefinition());
      if (problem.empty())
        problem = points_writer_.useDefinition(message.getDataType(), message.getMessageDefinition());
      if (problem.empty())
      {
        scan_pub_ = ros_io::advertise(pnh_, scan_writer_.type(), "scan", 1);
        points_pub_ = ros_io::advertise(pnh_, points_writer_.type(), "points", 1);
      }
    }
    if (!problem.empty())
    {
      ROS_ERROR("legacy_output_test_publisher: %s", problem.c_str());
      return;
    }
    std::vector<OutputPoint> returns;
    for (std::uint32_t i = 0; i < sweep_.beamCount(); ++i)
      if (sweep_.echoes[0].points[i].allFinite())
        returns.push_back(OutputPoint{ sweep_.echoes[0].points[i], sweep_.echoes[0].intensities[i],
                                       ohm_mirror_detector3d::core::Label::valid, 1, i });
    scan_pub_.publish(scan_writer_.write(header, sweep_));
    // The legacy decoder's sweeps are in the scanner's frame: their ranges are from its origin.
    points_pub_.publish(points_writer_.write(header, returns, Eigen::Vector3f::Zero()));
  }

  ros::NodeHandle& pnh_;
  std::vector<OutputPoint> builtin_points_;
  ros_io::LegacyPointSetWriter builtin_writer_;
  ros_io::LegacyScanWriter scan_writer_;
  ros_io::LegacyPointSetWriter points_writer_;
  ros_io::Hokuyo3dLegacyDecoder decoder_;
  ohm_mirror_detector3d::core::Sweep sweep_;
  ros::Publisher builtin_pub_, scan_pub_, points_pub_;
  ros::Subscriber driver_sub_;
  ros::WallTimer timer_;
};
}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "legacy_output_test_publisher");
  ros::NodeHandle pnh("~");
  LegacyOutputPublisher publisher(pnh);
  ros::spin();
  return 0;
}
