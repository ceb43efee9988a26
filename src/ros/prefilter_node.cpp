// Node ohm_mirror_prefilter3d: runs PreFilterNodelet in its own process, for users who
// do not use a nodelet manager. Same topics and parameters as the nodelet.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "ohm_mirror_prefilter3d");
  nodelet::Loader loader(false);
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string nodelet_argv;
  if (!loader.load(ros::this_node::getName(), "ohm_mirror_detector3d/PreFilterNodelet", remappings, nodelet_argv))
  {
    ROS_FATAL("ohm_mirror_prefilter3d: the pre-filter did not start (see the error above)");
    return 1;
  }
  ros::spin();
  return 0;
}
