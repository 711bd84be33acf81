#!/usr/bin/env bash
# roslaunch env-loader for a machine of distributed.launch, then the node's command line.
# From a source tree: the environment the project's scripts use (Debian's python first,
# the catkin devel space sourced; VALERANT_BUILD may name another build directory).
# Installed (PREFIX/share/valerant/launch): the install space's own setup.
here="$(dirname "$(readlink -f "$0")")"
if [ -f "$here/../scripts/env.sh" ]; then
  source "$here/../scripts/env.sh"
  valerant_source_workspace
else
  source "$here/../../../setup.bash"
fi
exec "$@"
