"""One core, two front-ends (README: "Package layout"): the core and the algorithms import no ROS at all, the ROS 2
front-end nothing of ROS 1, and the ROS 1 node nothing of ROS 2. Every import counts, also one inside a function,
and so does every module of the package that a front-end's module imports, down to the last."""
import ast
import os
import pathlib

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2] / "src"
PACKAGE = SOURCE / "cssr_system"
ANIMATE = PACKAGE / "animate_behaviour"
ROS1 = {"rospy", "actionlib", "actionlib_msgs", "genpy", "rospkg", "roslib", "rosgraph", "rostest",
        "dynamic_reconfigure", "cssr_system.msg", "cssr_system.srv", "cssr_system.cfg",
        "cssr_system.animate_behaviour.node", "cssr_system.animate_behaviour.rospy_compat"}
ROS2 = {"rclpy", "rcl_interfaces", "action_msgs", "builtin_interfaces", "unique_identifier_msgs", "launch",
        "launch_ros", "ament_index_python", "cssr_system_interfaces", "cssr_system.ros2"}
MESSAGES = {"std_msgs", "std_srvs", "sensor_msgs", "geometry_msgs", "trajectory_msgs", "control_msgs", "nav_msgs",
            "diagnostic_msgs", "naoqi_bridge_msgs"}
# The one shared module that asks each ROS for the package's folder, each only where it runs (ROS_VERSION).
PACKAGE_INDEX = PACKAGE / "package_files.py"


def imports_of(path: pathlib.Path):
    tree = ast.parse(path.read_text(), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            yield node.module
            yield from ("%s.%s" % (node.module, alias.name) for alias in node.names)


def module_file(name: str):
    base = SOURCE.joinpath(*name.split("."))
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def closure(paths):
    """Every file of the package that `paths` import, directly or not, with the names each imports."""
    seen, todo = {}, list(paths)
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen[path] = set(imports_of(path))
        for name in seen[path]:
            target = module_file(name) if name.startswith("cssr_system") else None
            if target is not None and target not in seen and target != PACKAGE_INDEX:
                todo.append(target)
    return seen


def offending(paths, forbidden):
    return sorted("%s: %s" % (os.path.relpath(path, SOURCE), name) for path, names in closure(paths).items()
                  for name in names if any(name == bad or name.startswith(bad + ".") for bad in forbidden))


def files(*folders):
    return [path for folder in folders for path in sorted(folder.rglob("*.py"))]


def test_the_core_and_the_algorithms_import_no_ros():
    assert offending(files(ANIMATE / "core", ANIMATE / "motion"), ROS1 | ROS2 | MESSAGES) == []


def test_the_ros_2_front_end_imports_nothing_of_ros_1():
    assert files(PACKAGE / "ros2"), "the ROS 2 front-end is there"
    assert offending(files(PACKAGE / "ros2"), ROS1) == []


def test_the_ros_1_node_imports_nothing_of_ros_2():
    assert offending(files(ANIMATE / "node"), ROS2) == []


@pytest.mark.parametrize("line,caught", [
    ("import rospy", True), ("from actionlib.action_client import X", True),
    ("from cssr_system.animate_behaviour.node import goals", True), ("import numpy", False),
    ("from cssr_system.pepper import joint_table", False)])
def test_the_check_finds_what_it_looks_for(tmp_path, line, caught):
    module = tmp_path / "module.py"
    module.write_text("def f():\n    " + line + "\n")
    assert bool(offending([module], ROS1)) == caught
