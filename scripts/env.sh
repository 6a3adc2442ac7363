# Sourced by the other scripts: the workspace and its environment.
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
WS=${VT_WS:-$REPO/.ws}
set +u
if [[ -f $WS/devel/setup.bash ]]; then source "$WS/devel/setup.bash"; fi
set -u
# ROS's Python tools must run with Debian's python3, not a pyenv one.
export PATH=/usr/bin:$PATH
export ROS_PYTHON_VERSION=3
