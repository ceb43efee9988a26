// The original node's outputs (its pub_* parameters), in its message types, so that downstream
// nodes compiled against the original driver's package ohm_hokuyo3d receive what they always
// did: which outputs there are, what each carries, and their publishers in the nodelet. The
// messages are written by legacy_output.h's writers, in the definition the driver's connection
// carries once it has come (the built-in reconstruction before).
//
//   pub_scan            the prefiltered scan                        ohm_hokuyo3d/CoordDistMulti
//   pub_object          points on any object (mirror, glass, unknown) ohm_hokuyo3d/CoordDist
//   pub_transp          points on glass                              "
//   pub_mirror          points on mirrors                            "
//   pub_affected        points behind any object, as measured        "
//   pub_behTransp       points behind glass                          "
//   pub_behMirror       points behind mirrors (phantoms), as measured "
//   pub_backprojMirror  the phantoms back-projected                   "
//   pub_cleaned         the points for mapping (those of ~cleaned)   "
//   pub_marker          the objects' outlines                        visualization_msgs/Marker
#pragma once

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/Marker.h>

#include <Eigen/Core>
#include <mutex>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/pipeline.h"
#include "ohm_mirror_detector3d/ros/legacy_output.h"
#include "ohm_mirror_detector3d/ros/parameters.h"

namespace ohm_mirror_detector3d
{
namespace ros_io
{
enum class LegacyContent
{
  scan,
  object,
  transparent,
  mirror,
  affected,
  behind_transparent,
  behind_mirror,
  back_projected,
  cleaned,
  marker,
};

struct LegacyOutput
{
  const char* parameter;      // the original's parameter naming its topic, e.g. "pub_scan"
  const char* default_topic;  // in input_mode hokuyo3d_legacy when the parameter is not set (private)
  LegacyContent content;
};

// The original's outputs in the order of its launch file.
const std::vector<LegacyOutput>& legacyOutputs();

// The points of a point-set output (every content but scan and marker): for back_projected and
// cleaned those of result.cleaned (back-projected), for the others the sweep's points with the
// content's labels as measured, in beam order, echo 1 before echo 2, a single return that echo 2
// repeats once (as in result.cleaned).
void collectLegacyPoints(LegacyContent content, const core::Sweep& sweep, const core::PipelineResult& result,
                         std::vector<core::OutputPoint>& points);

// The objects' outlines as one marker (ns "objects", id 0): a LINE_LIST, four segments per
// object, coloured per vertex by type as ~markers colours them; DELETE when there is no object.
void toLegacyMarker(const std_msgs::Header& header, const std::vector<core::ReflectiveObject>& objects,
                    visualization_msgs::Marker& marker);

// The nodelet's publishers of the original's outputs. Thread-safe: the definition may change on
// the input's thread while the subscription is checked on another.
class LegacyPublishers
{
public:
  // Advertises on `nh` each output whose parameter is set in `source` (on that topic) and, with
  // `every_output` (input_mode hokuyo3d_legacy), the others on their default topics. `on_connection`
  // is called when a subscriber comes or goes.
  void advertise(ros::NodeHandle& nh, const ParamSource& source, bool every_output,
                 const ros::SubscriberStatusCallback& on_connection);

  bool anySubscribed() const;
  // "pub_scan /prefiltered_scan, ..." for the log; "" when none is advertised.
  std::string describe() const;

  // Writes the messages in the definition of the driver's connection from now on (`datatype`,
  // full `definition` of its CoordDistMulti); a publisher whose type changes is advertised again.
  // Returns "" or why the definition cannot be used (the previous one stays).
  std::string useDefinition(const std::string& datatype, const std::string& definition);

  // Publishes every output that has a subscriber; `origin`: the scanner's position in the
  // header's frame (distances of the point sets).
  void publish(const std_msgs::Header& header, const core::Sweep& sweep, const core::PipelineResult& result,
               const Eigen::Vector3f& origin);

private:
  struct Active
  {
    const LegacyOutput* output;
    std::string topic;
    ros::Publisher publisher;
  };

  ros::Publisher advertiseOne(const Active& active);
  // Advertises again, after a change of definition, the scan (`scan`) or every point set.
  void readvertise(bool scan);

  ros::NodeHandle nh_;
  ros::SubscriberStatusCallback on_connection_;
  mutable std::mutex mutex_;  // guards the publishers in active_
  std::vector<Active> active_;
  LegacyScanWriter scan_writer_;
  LegacyPointSetWriter point_writer_;
  std::vector<core::OutputPoint> points_;  // reused
};

}  // namespace ros_io
}  // namespace ohm_mirror_detector3d
