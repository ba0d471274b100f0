#!/usr/bin/env bash
# Installs the Debian 12 packages msm_sim needs to build and test (ROS Noetic from Debian's own
# archive; there is no /opt/ros and no rosdep here). Installs only what is missing; uses sudo when
# not root. Safe to run repeatedly.
set -euo pipefail

packages=(
  build-essential cmake
  catkin python3-catkin-pkg ros-core-dev ros-message-generation ros-message-runtime
  libroscpp-dev librosbag-dev libtf2-dev libtf2-ros-dev libros-rosgraph-msgs-dev
  libstd-msgs-dev libgeometry-msgs-dev ros-std-msgs ros-geometry-msgs
  libsensor-msgs-dev libvisualization-msgs-dev libstd-srvs-dev libdiagnostic-msgs-dev
  ros-sensor-msgs ros-visualization-msgs ros-std-srvs ros-diagnostic-msgs
  python3-sensor-msgs python3-visualization-msgs python3-std-srvs python3-diagnostic-msgs
  libtf2-geometry-msgs-dev libnodelet-dev libnodeletlib-dev libnodeletlib-tools pluginlib-dev
  python3-rostest librostest-dev python3-roslaunch
  liburdfdom-dev libassimp-dev libeigen3-dev libcgal-dev
  libcli11-dev nlohmann-json3-dev libyaml-cpp-dev python3-matplotlib
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  googletest libgtest-dev libgmock-dev libbenchmark-dev
  # The benchmark peer: bench/bullet_comparison_benchmark.cpp times btSoftBody on the same lattice.
  libbullet-dev
  # Test set-up: the mesh importer is checked against every model assimp ships.
  assimp-testmodels
  # Test set-up: the cantilever's finite-element reference (core::RunCalculixCantilever runs ccx).
  calculix-ccx
  # The robot demo and its check with a real client (rviz on a virtual display).
  ros-robot-state-publisher python3-rospy rviz xvfb imagemagick
  # The grasp demo's script reads the object's frame from /tf.
  python3-tf2-msgs
  # The Python module msm_sim (docs/python.md): the extension, its arrays, the sweeps on Dask
  # with their grid files and progress bar, and its tests.
  pybind11-dev python3-pybind11 python3-numpy python3-yaml python3-distributed python3-tqdm
  python3-pytest
)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "install_dependencies: missing packages (${missing[*]}) and neither root nor sudo" >&2
  exit 1
fi
echo "install_dependencies: installing ${missing[*]}"
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq \
  "${missing[@]}"
