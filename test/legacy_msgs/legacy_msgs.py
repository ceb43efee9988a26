"""The original driver's message types as a node compiled against ohm_hokuyo3d has them, from
the reconstructed .msg files beside this module: full definitions and md5sums computed by
genmsg, classes generated from them at run time (genpy.dynamic). No package is built."""
import os

MSG_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'ohm_hokuyo3d', 'msg')
PACKAGE = 'ohm_hokuyo3d'
TYPES = ('CoordDistMulti', 'CoordDist', 'Coord', 'Dist')


def _loaded(type_name):
    import genmsg
    import genmsg.msg_loader
    import rospkg
    search_path = {PACKAGE: [MSG_DIR], 'std_msgs': [os.path.join(rospkg.RosPack().get_path('std_msgs'), 'msg')]}
    context = genmsg.MsgContext.create_default()
    spec = genmsg.msg_loader.load_msg_by_type(context, type_name, search_path)
    genmsg.msg_loader.load_depends(context, spec, search_path)
    return context, spec


def md5sum(type_name):
    """genmsg's md5sum of `type_name` ('ohm_hokuyo3d/CoordDist'), what roscpp and rospy compare."""
    import genmsg.gentools
    return genmsg.gentools.compute_md5(*_loaded(type_name))


def full_definition(type_name):
    """The definition text a publisher of `type_name` sends (genmsg's compute_full_text)."""
    import genmsg.gentools
    return genmsg.gentools.compute_full_text(*_loaded(type_name))


def classes_by_name(type_name):
    """{type name: class} for `type_name` and its nested types, generated at run time."""
    import genpy.dynamic
    return genpy.dynamic.generate_dynamic(type_name, full_definition(type_name))


def message_class(type_name):
    """A message class of `type_name`, generated at run time from the .msg files."""
    return classes_by_name(type_name)[type_name]
