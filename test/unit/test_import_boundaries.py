"""Two adapters over one core (README: "Package layout"). Every module under src/ is read with `ast` (every import
counts, also one inside a function) and must keep to its room:
- a ROS 1 import (rospy, actionlib, dynamic_reconfigure, rosgraph, roslaunch, rostest, genpy, a ROS 1 message
  package) only in ros1/, a ROS 2 import (rclpy, a ROS 2 interface package) only in ros2/;
- a module outside the adapters imports neither adapter;
- each room imports only from its own floor and the floors below it, and no modules import each other in a cycle.
Each failure names the file and the import."""
import ast
import pathlib

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2] / "src"
PACKAGE = SOURCE / "cssr_system"
ROS1 = {"rospy", "actionlib", "actionlib_msgs", "genpy", "rospkg", "roslib", "rosgraph", "roslaunch", "rostest",
        "rosbag", "dynamic_reconfigure", "catkin_pkg", "cssr_system.msg", "cssr_system.srv", "cssr_system.cfg"}
ROS2 = {"rclpy", "rcl_interfaces", "action_msgs", "builtin_interfaces", "unique_identifier_msgs", "launch",
        "launch_ros", "ament_index_python", "rosidl_runtime_py", "cssr_system_interfaces"}
# Message packages both ROSes have by the same name: the folder a module stands in tells which ROS it speaks.
MESSAGES = {"std_msgs", "std_srvs", "sensor_msgs", "geometry_msgs", "trajectory_msgs", "control_msgs", "nav_msgs",
            "diagnostic_msgs", "naoqi_bridge_msgs"}
ADAPTERS = {"ros1": ROS1, "ros2": ROS2}
# The rooms of src/cssr_system/, each on a floor: a room imports from its own floor and those below it.
FLOORS = {"package_files": 0, "pepper": 0,
          "animate_behaviour": 1,
          "motion": 2, "figure": 2,
          "core": 3,
          "recording": 4, "harness": 5, "demo": 5, "soak": 5,
          "ros1": 6, "ros2": 6}


def imports_of(source: str, filename: str = "<module>"):
    """(line, imported name) of every import: `from a.b import c` gives a.b and a.b.c."""
    for node in ast.walk(ast.parse(source, filename)):
        if isinstance(node, ast.Import):
            yield from ((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            yield node.lineno, node.module
            yield from ((node.lineno, "%s.%s" % (node.module, alias.name)) for alias in node.names)


def within(name: str, prefixes) -> bool:
    return any(name == prefix or name.startswith(prefix + ".") for prefix in prefixes)


def room_of(name: str) -> str:
    """The room of a module of the package, by its dotted name or its path under src/cssr_system/."""
    parts = name.replace("/", ".").split(".")
    return parts[1] if parts[0] == "cssr_system" and len(parts) > 1 else parts[0]


def strays(room: str, imports):
    """What a module of `room` may not import, among `imports` [(line, name)]: one finding per import statement."""
    reported = set()
    for line, name, why in reasons(room, imports):
        if line not in reported:
            reported.add(line)
            yield line, name, why


def reasons(room: str, imports):
    for line, name in imports:
        if within(name, MESSAGES | ROS1 | ROS2) and not within(name, ADAPTERS.get(room, set()) | MESSAGES):
            yield line, name, "a ROS import outside its adapter (ros1/ or ros2/)"
        elif within(name, MESSAGES) and room not in ADAPTERS:
            yield line, name, "a message package outside the adapters"
        elif within(name, {"cssr_system"}) and not within(name, ROS1 | ROS2):
            target = room_of(name)
            if target in ADAPTERS and target != room:
                yield line, name, "an adapter imported from %s/" % room
            elif FLOORS.get(target, 0) > FLOORS[room]:
                yield line, name, "a room above %s/ (%s/)" % (room, target)


def modules():
    return sorted(PACKAGE.rglob("*.py"))


def module_room(path: pathlib.Path) -> str:
    relative = path.relative_to(PACKAGE)
    return relative.parts[0] if len(relative.parts) > 1 else relative.stem


def test_every_room_of_the_package_has_a_floor():
    rooms = {module_room(path) for path in modules()} - {"__init__"}
    assert rooms == set(FLOORS)


def test_every_module_keeps_to_its_room():
    found = ["%s:%d: %s: %s" % (path.relative_to(SOURCE), line, name, why) for path in modules()
             for line, name, why in strays(module_room(path), imports_of(path.read_text(), str(path)))]
    assert found == []


def test_the_two_adapters_are_there_and_each_speaks_its_ros():
    for room, ros in ADAPTERS.items():
        speaking = [path for path in (PACKAGE / room).glob("*.py")
                    if any(within(name, ros) for _, name in imports_of(path.read_text()))]
        assert len(speaking) >= 10, room


def module_name(path: pathlib.Path) -> str:
    parts = path.relative_to(SOURCE).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def test_no_modules_import_each_other_in_a_cycle():
    names = {module_name(path): path for path in modules()}
    graph = {name: {imported for _, imported in imports_of(path.read_text()) if imported in names and imported != name}
             for name, path in names.items()}
    assert [cycle for cycle in map(lambda start: cycle_from(start, graph), sorted(graph)) if cycle] == []


def cycle_from(start: str, graph) -> list:
    """A path of imports from `start` back to itself ([] if none)."""
    todo, seen = [(start, [start])], set()
    while todo:
        name, path = todo.pop()
        for imported in sorted(graph[name]):
            if imported == start:
                return path + [start]
            if imported not in seen:
                seen.add(imported)
                todo.append((imported, path + [imported]))
    return []


@pytest.mark.parametrize("room,line,caught", [
    ("core", "import rospy", "a ROS import outside its adapter (ros1/ or ros2/)"),
    ("ros2", "from actionlib.action_client import X", "a ROS import outside its adapter (ros1/ or ros2/)"),
    ("ros1", "import rclpy", "a ROS import outside its adapter (ros1/ or ros2/)"),
    ("ros1", "from cssr_system_interfaces.msg import AnimateBehaviourStatus",
     "a ROS import outside its adapter (ros1/ or ros2/)"),
    ("harness", "from sensor_msgs.msg import JointState", "a message package outside the adapters"),
    ("demo", "from cssr_system.ros1 import trajectory_client", "an adapter imported from demo/"),
    ("ros2", "from cssr_system.ros1.rospy_compat import caller_of", "an adapter imported from ros2/"),
    ("recording", "from cssr_system.demo.gesture import PLAY_TOPIC", "a room above recording/ (demo/)"),
    ("animate_behaviour", "from cssr_system.core.console import console", "a room above animate_behaviour/ (core/)"),
    ("ros1", "from cssr_system.msg import AnimateBehaviourStatus", None),
    ("ros1", "import rospy", None), ("ros2", "from sensor_msgs.msg import JointState", None),
    ("core", "import numpy", None), ("core", "from cssr_system.pepper import joint_table", None)])
def test_the_check_finds_what_it_looks_for(room, line, caught):
    found = [why for _, _, why in strays(room, imports_of("def f():\n    " + line + "\n"))]
    assert found == ([caught] if caught else [])


def test_the_cycle_check_finds_a_cycle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert cycle_from("a", graph) == ["a", "b", "c", "a"]
    assert cycle_from("d", graph) == []
