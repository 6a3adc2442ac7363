#!/usr/bin/env bash
# Installs what virtual_tryon needs from Debian 12's own ROS 1 packages. Skips what is there.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git
  ros-base-dev ros-core catkin python3-catkin-pkg python3-rostest librostest-dev
  python3-rosbag librosbag-dev rosbash
  libeigen3-dev libpcl-dev libfcl-dev libpcl-conversions-dev libyaml-cpp-dev
  libtf2-dev libtf2-ros-dev libtf2-eigen-dev
  libstd-msgs-dev libgeometry-msgs-dev libsensor-msgs-dev libshape-msgs-dev
  libpcl-msgs-dev libvisualization-msgs-dev
  ros-std-msgs ros-geometry-msgs ros-sensor-msgs ros-shape-msgs ros-pcl-msgs ros-visualization-msgs
  python3-std-msgs python3-geometry-msgs python3-sensor-msgs python3-pcl-msgs python3-visualization-msgs
  libgtest-dev googletest
  libactionlib-dev libactionlib-msgs-dev ros-actionlib-msgs python3-actionlib python3-actionlib-msgs
  libpcl-dev python3-matplotlib python3-numpy
  libvtk9-dev xvfb xauth
  clang libfuzzer-14-dev
  nlohmann-json3-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup: all ${#PACKAGES[@]} Debian packages present"
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
# A mirror that fails for a moment (a CI run once lost its whole first stage to one) is asked
# again: each download up to 3 times (Acquire::Retries), each command up to 3 times, a pause
# between.
retry() {
  local attempt
  for attempt in 1 2 3; do
    "$@" && return 0
    echo "setup: attempt $attempt of 3 failed: $*" >&2
    ((attempt < 3)) && sleep $((20 * attempt))
  done
  return 1
}
APT=($SUDO apt-get -o Acquire::Retries=3 -o DPkg::Lock::Timeout=120)
retry "${APT[@]}" update -qq
retry "${APT[@]}" install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
