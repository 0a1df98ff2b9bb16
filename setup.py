# Installs the Python modules under src/ (called by catkin_python_setup; not for direct use).
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["cssr_system"], package_dir={"": "src"}))
