# Installs the Python package src/ohm_mirror_detector3d through catkin_python_setup();
# never run it directly (`pip install .` uses pyproject.toml and its own backend, not this file).
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup
from setuptools.dist import Distribution


class CatkinDistribution(Distribution):
    """Reads setup.cfg-style files but not pyproject.toml: that file describes the pip build, and
    setuptools >= 61 would otherwise apply its [project] table to catkin's install (another
    description, its dependencies and a console script in the install space's bin)."""

    def parse_config_files(self, filenames=None, ignore_option_errors=False):
        if filenames is None:
            filenames = self.find_config_files()
        super().parse_config_files([f for f in filenames if not str(f).endswith('.toml')], ignore_option_errors)


setup(distclass=CatkinDistribution, **generate_distutils_setup(
    packages=['ohm_mirror_detector3d'],
    package_dir={'': 'src'},
))
