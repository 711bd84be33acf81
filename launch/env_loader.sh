#!/usr/bin/env bash
# roslaunch env-loader for a machine of distributed.launch: the same environment the
# project's scripts use (Debian's python first, the catkin workspace sourced), then the
# node's command line. VALERANT_BUILD may name another build directory.
source "$(dirname "$(readlink -f "$0")")/../scripts/env.sh"
valerant_source_workspace
exec "$@"
