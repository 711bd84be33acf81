# Sourced by every script: the environment the ROS python tools and our build need.
# The machine's default python3 may not be Debian's; roslaunch, rostest and catkin
# only work with /usr/bin/python3, so /usr/bin goes first on PATH.
VALERANT_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VALERANT_BUILD="${VALERANT_BUILD:-$VALERANT_ROOT/.ws/build}"
export PATH="/usr/bin:$PATH"
export VALERANT_ROOT VALERANT_BUILD
# ROS_PACKAGE_PATH must see the source tree so roslaunch/rostest find launch files.
valerant_source_workspace() {
  if [ -f "$VALERANT_BUILD/devel/setup.bash" ]; then
    # ROS's setup scripts read unset variables: relax nounset while sourcing them.
    local nounset=0
    case $- in *u*) nounset=1 ;; esac
    set +u
    # shellcheck disable=SC1091
    source "$VALERANT_BUILD/devel/setup.bash"
    [ "$nounset" = 1 ] && set -u
  fi
  export ROS_PACKAGE_PATH="$VALERANT_ROOT${ROS_PACKAGE_PATH:+:$ROS_PACKAGE_PATH}"
}
