#!/usr/bin/env bash
# Install belvedere into the active Python environment.
#
#   ./scripts/install.sh         the user's install: belvedere and its runtime dependencies
#                                (`pip install .`), and the Debian libraries the physics
#                                simulation's cameras render with (Mesa's EGL, software OpenGL)
#   ./scripts/install.sh --dev   the developer's install (what CI and ./scripts/test.sh use):
#                                belvedere editable with its test tools (`pip install -e
#                                ".[test]"`), the test oracles, Chromium, and Debian's ROS 1
#
# Debian packages are installed with apt-get when we are root or have sudo; elsewhere the
# missing ones are named and the Python part goes on.
set -euo pipefail
cd "$(dirname "$0")/.."

dev=0
case "${1:-}" in
  "") ;;
  --dev) dev=1 ;;
  -h | --help)
    sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
    exit 0
    ;;
  *)
    echo "usage: $0 [--dev]" >&2
    exit 2
    ;;
esac

# What MuJoCo's offscreen rendering loads through MUJOCO_GL=egl (the physics cameras and
# Kinects): libglvnd's EGL and OpenGL dispatchers and Mesa's EGL with its llvmpipe driver;
# Graphviz's dot lays out rqt_graph's, view_frames' and urdf_to_graphiz's pictures.
RUNTIME_DEBIAN=(libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 graphviz)

# check_urdf (the URDF oracle), Chromium (the viewer's browser tests), and Debian's ROS 1
# (ros_comm 1.15: roscore, roslaunch, rospy, robot_state_publisher, tf, rosbag, rviz) with
# the message packages rospack needs, the oracle of the differential tests; xvfb and xauth
# run Debian's rviz for tests/viewer/rviz_pair.py; catkin, roscpp and message generation build
# the course's C++ nodes (tests/ros1wire/catkin.py); python3-cv-bridge is cv_bridge's oracle;
# python3-rostest (rostest and its stock test nodes) is belvedere test's oracle
DEV_DEBIAN=(
  liburdfdom-tools chromium
  ros-base ros-robot-state-publisher python3-rospy python3-roslaunch python3-rostopic
  python3-rosservice python3-tf2-ros python3-tf python3-actionlib python3-std-srvs python3-nav-msgs
  python3-cv-bridge python3-rostest catkin libroscpp-dev ros-message-generation g++
  libstd-msgs-dev libgeometry-msgs-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev
  libros-rosgraph-msgs-dev libactionlib-msgs-dev libtrajectory-msgs-dev
  libvisualization-msgs-dev libdiagnostic-msgs-dev libstd-srvs-dev
  rviz xvfb xauth ros-image-view
)

debian=("${RUNTIME_DEBIAN[@]}")
if [ "$dev" = 1 ]; then debian+=("${DEV_DEBIAN[@]}"); fi

if command -v dpkg >/dev/null 2>&1 && command -v apt-get >/dev/null 2>&1; then
  missing=()
  for p in "${debian[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" = 0 ]; then
      SUDO=""
    elif command -v sudo >/dev/null 2>&1; then
      SUDO="sudo"
    else
      SUDO="none"
    fi
    if [ "$SUDO" = none ]; then
      echo "install.sh: not root and no sudo; install these Debian packages yourself:" >&2
      echo "  apt-get install ${missing[*]}" >&2
    else
      $SUDO apt-get update -qq
      $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
    fi
  fi
fi

if [ "$dev" = 0 ]; then
  python3 -m pip install -q .
  exit 0
fi

python3 -m pip install -q --upgrade pip
python3 -m pip install -q -e ".[test]"

# Test oracles that cannot share the environment with the 2.1.1 reference (same module name):
# ROS Melodic's xacro 1.13.3, for differential tests of the legacy dialects.
python3 -m pip install -q --no-deps --upgrade --target .oracles/xacro-1.13.3 xacro==1.13.3
