"""The ROS 2 package (ros2/cssr_system) declares what its programs import, and carries the ROS 1 package's version
(README: "On ROS 2")."""
import ast
import pathlib
import xml.etree.ElementTree as ElementTree

ROOT = pathlib.Path(__file__).resolve().parents[2]
ROS2_SOURCES = [ROOT / "src" / "cssr_system" / "ros2", ROOT / "ros2" / "cssr_system" / "launch"]
# The ROS 2 libraries beside the message packages (the names ending in _msgs, _srvs, _interfaces).
ROS_LIBRARIES = ("rclpy", "launch", "launch_ros", "ament_index_python")


def manifest(path: pathlib.Path):
    return ElementTree.parse(str(path)).getroot()


def imported_packages():
    names = set()
    for folder in ROS2_SOURCES:
        for path in folder.rglob("*.py"):
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.Import):
                    names |= {alias.name.split(".")[0] for alias in node.names}
                elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                    names.add(node.module.split(".")[0])
    return {name for name in names
            if name in ROS_LIBRARIES or name.endswith(("_msgs", "_srvs", "_interfaces"))}


def test_every_ros_package_the_ros_2_programs_import_is_an_exec_depend():
    declared = {element.text for element in manifest(ROOT / "ros2" / "cssr_system" / "package.xml").iter("exec_depend")}
    assert imported_packages(), "the ROS 2 programs are found"
    assert sorted(imported_packages() - declared) == []


def test_the_ros_2_package_has_the_ros_1_packages_version():
    assert manifest(ROOT / "ros2" / "cssr_system" / "package.xml").findtext("version") == \
        manifest(ROOT / "package.xml").findtext("version")
