"""animateBehaviour on ROS 2 (README: "ROS 2"), optionally with the simulated Pepper:

  ros2 launch cssr_system animate_behaviour.launch.py platform:=simulator simulated_pepper:=true
  ros2 launch cssr_system animate_behaviour.launch.py actuation:=joint_angles      (a real Pepper on naoqi_driver2)

Arguments: platform (robot or simulator: which topic file names the controllers), actuation (trajectory:
FollowJointTrajectory goals; joint_angles: /joint_angles calls for naoqi_driver2), config_file (the
configuration file), use_sim_time, simulated_pepper (true: also start the simulated Pepper, with driver
ideal, naoqi_dcm or naoqi_driver), ns (the robot's namespace, e.g. robot1; default: the root) and node_name
(default animateBehaviour; the node's services, status and action move with it). Every configuration key can also
be set on the node as a parameter."""
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    argument = LaunchConfiguration
    default_file = PathJoinSubstitution([FindPackageShare("cssr_system"), "config",
                                         "animateBehaviourConfiguration.ini"])
    return LaunchDescription([
        DeclareLaunchArgument("platform", default_value="robot", description="robot or simulator"),
        DeclareLaunchArgument("actuation", default_value="trajectory", description="trajectory or joint_angles"),
        DeclareLaunchArgument("config_file", default_value=default_file, description="the configuration file"),
        DeclareLaunchArgument("use_sim_time", default_value="false", description="follow /clock"),
        DeclareLaunchArgument("simulated_pepper", default_value="false", description="also start the simulated Pepper"),
        DeclareLaunchArgument("driver", default_value="ideal", description="the simulated Pepper's driver model"),
        DeclareLaunchArgument("ns", default_value="/", description="the robot's namespace (README: Several robots)"),
        DeclareLaunchArgument("node_name", default_value="animateBehaviour", description="the node's name"),
        Node(package="cssr_system", executable="simulated_pepper", name="simulatedPepper", output="screen",
             namespace=argument("ns"),
             condition=IfCondition(argument("simulated_pepper")),
             parameters=[{"platform": argument("platform"), "driver": argument("driver"),
                          "use_sim_time": argument("use_sim_time")}]),
        Node(package="cssr_system", executable="animate_behaviour", name=argument("node_name"), output="screen",
             namespace=argument("ns"),
             parameters=[{"configFile": argument("config_file"), "platform": argument("platform"),
                          "actuation": argument("actuation"), "use_sim_time": argument("use_sim_time")}]),
    ])
