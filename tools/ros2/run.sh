#!/usr/bin/env bash
# Runs one command in the ROS 2 environment of this clone (tools/ros2/env.sh), e.g.
#   bash tools/ros2/run.sh python3 -c 'import rclpy'
#   CSSR_ROS2_DISTRO=kilted bash tools/ros2/run.sh python3 -c 'import rclpy'   # Jazzy's by default
# from any shell: a ROS 1 shell's variables would mix the two ROS, so the command starts from an empty
# environment that keeps only what it needs and what says which workspace, distribution and ROS 2 domain to use.
# Run tools/ros2/setup.sh first (with the same CSSR_ROS2_DISTRO).
set -euo pipefail
[ $# -gt 0 ] || { echo "usage: $0 COMMAND [ARGUMENT...]" >&2; exit 2; }
tools_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P)

keep=(HOME="$HOME" PATH=/usr/local/bin:/usr/bin:/bin TERM="${TERM:-dumb}" LANG="${LANG:-C.UTF-8}")
# The workspace (and what names it: tools/common.sh), the distribution (CSSR_ROS2_DISTRO), the ROS 2 domain and
# discovery range, ROS 2's logging settings, and the TLS certificates a program may be pointed at.
for name in $(compgen -e); do
  case $name in
    WORKSPACE_DIR|CSSR_*|XDG_CACHE_HOME|ROS_DOMAIN_ID|ROS_AUTOMATIC_DISCOVERY_RANGE|ROS_STATIC_PEERS|RCUTILS_*|\
    PYTHONUNBUFFERED|PYTHONDONTWRITEBYTECODE|SSL_CERT_FILE|SSL_CERT_DIR) keep+=("$name=${!name}") ;;
  esac
done

exec env -i "${keep[@]}" bash -c 'source "$1/env.sh" && shift && exec "$@"' _ "$tools_dir" "$@"
