#!/usr/bin/env bash
# Install belvedere and everything its tests need into the active Python environment.
# Debian packages the tests use are installed when we are root (or have sudo).
set -euo pipefail
cd "$(dirname "$0")/.."

# check_urdf (URDF oracle), the viewer's browser tests, software OpenGL through EGL (Mesa
# llvmpipe) for MuJoCo's offscreen camera rendering, and Debian's ROS 1 (ros_comm 1.15:
# roscore, roslaunch, rospy, robot_state_publisher, tf) with the message packages rospack
# needs, as the oracle of the differential tests
DEBIAN_PACKAGES=(
  liburdfdom-tools chromium libegl1 libegl-mesa0 libgl1-mesa-dri
  ros-base ros-robot-state-publisher python3-rospy python3-roslaunch python3-rostopic
  python3-rosservice python3-tf2-ros python3-tf python3-actionlib python3-std-srvs
  libstd-msgs-dev libgeometry-msgs-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev
  libros-rosgraph-msgs-dev libactionlib-msgs-dev libtrajectory-msgs-dev
  libvisualization-msgs-dev libdiagnostic-msgs-dev libstd-srvs-dev
  rviz xvfb xauth
)

if [ ${#DEBIAN_PACKAGES[@]} -gt 0 ] && command -v apt-get >/dev/null 2>&1; then
  missing=()
  for p in "${DEBIAN_PACKAGES[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
  fi
fi

python -m pip install -q --upgrade pip
python -m pip install -q -e ".[test]"

# Test oracles that cannot share the environment with the 2.1.1 reference (same module name):
# ROS Melodic's xacro 1.13.3, for differential tests of the legacy dialects.
python -m pip install -q --no-deps --upgrade --target .oracles/xacro-1.13.3 xacro==1.13.3
