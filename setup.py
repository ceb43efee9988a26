# Installs the Python package src/ohm_mirror_detector3d through catkin_python_setup();
# never run it directly.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(
    packages=['ohm_mirror_detector3d'],
    package_dir={'': 'src'},
))
