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


LAUNCH_FILE = ROOT / "ros2" / "cssr_system" / "launch" / "animate_behaviour.launch.py"


def launch_calls(name: str):
    """The keyword arguments of every call to `name` in the ROS 2 launch file (it needs ROS 2's launch to run)."""
    tree = ast.parse(LAUNCH_FILE.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == name:
            yield {keyword.arg: keyword.value for keyword in node.keywords}, node.args


def test_the_launch_file_starts_the_package_s_programs():
    executables = {ast.literal_eval(keywords["executable"]) for keywords, _ in launch_calls("Node")}
    assert executables == {"animate_behaviour", "simulated_pepper"}
    assert all((ROOT / "ros2" / "cssr_system" / "scripts" / name).is_file() for name in executables)


def test_every_launch_argument_is_documented():
    documentation = (ROOT / "doc" / "ros2.md").read_text()
    arguments = [ast.literal_eval(args[0]) for _, args in launch_calls("DeclareLaunchArgument")]
    assert arguments and all("`%s`" % argument in documentation for argument in arguments)


def program_declarations(module: str):
    """(NODE_NAME, the names of PARAMETERS) of a ROS 2 program's module, read from its source (it imports rclpy)."""
    tree = ast.parse((ROOT / "src" / "cssr_system" / "ros2" / (module + ".py")).read_text())
    values = {}
    for node in tree.body:
        target = node.targets[0] if isinstance(node, ast.Assign) else getattr(node, "target", None)
        if isinstance(target, ast.Name) and target.id in ("NODE_NAME", "PARAMETERS") and node.value is not None:
            values[target.id] = node.value
    return (ast.literal_eval(values["NODE_NAME"]),
            {ast.literal_eval(pair.elts[0]) for pair in values["PARAMETERS"].elts})


def node_parameter_names(keywords) -> set:
    (parameters,) = keywords["parameters"].elts
    return {ast.literal_eval(key) for key in parameters.keys}


def test_the_launch_file_gives_each_program_its_name_and_only_parameters_it_declares():
    """`ros2 launch` cannot run here (no launch or launch_ros on PyPI: doc/ros2.md), so the launch file is read: each
    node's name and parameters must be those its program declares (use_sim_time is every rclpy node's)."""
    from cssr_system.animate_behaviour.configuration import KEYS
    from cssr_system.animate_behaviour.contract import NODE_NAME

    nodes = {ast.literal_eval(keywords["executable"]): keywords for keywords, _ in launch_calls("Node")}
    defaults = {ast.literal_eval(args[0]): keywords.get("default_value")
                for keywords, args in launch_calls("DeclareLaunchArgument")}
    simulator_name, simulator_parameters = program_declarations("simulated_pepper_node")
    assert ast.literal_eval(nodes["simulated_pepper"]["name"]) == simulator_name
    assert node_parameter_names(nodes["simulated_pepper"]) <= simulator_parameters | {"use_sim_time"}
    assert ast.literal_eval(defaults["node_name"]) == NODE_NAME
    animate_parameters = set(KEYS) | {"configFile", "logFile", "use_sim_time"}  # src/cssr_system/ros2/parameters.py
    assert node_parameter_names(nodes["animate_behaviour"]) <= animate_parameters
    assert {"configFile", "platform", "actuation"} <= node_parameter_names(nodes["animate_behaviour"])


def test_the_launch_file_s_default_configuration_file_is_the_shipped_one():
    (default,) = [keywords["default_value"] for keywords, args in launch_calls("DeclareLaunchArgument")
                  if ast.literal_eval(args[0]) == "config_file"]
    # default_value=default_file, assigned PathJoinSubstitution([FindPackageShare("cssr_system"), "config", ...]).
    (assigned,) = [node.value for node in ast.walk(ast.parse(LAUNCH_FILE.read_text()))
                   if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", None) == default.id]
    share, *parts = assigned.args[0].elts
    assert ast.literal_eval(share.args[0]) == "cssr_system"
    assert ROOT.joinpath(*map(ast.literal_eval, parts)).is_file(), "installed as share/cssr_system/config/..."
