"""The Python package msm_sim (src/msm_sim/), installed by catkin_python_setup()."""
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["msm_sim"], package_dir={"": "src"}))
