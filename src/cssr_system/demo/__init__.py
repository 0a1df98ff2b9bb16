"""The demo's ROS-free parts (`make demo`, launch/animateBehaviourDemo.launch): the run's schedule, lines and verdict
(`demo_run`, `live_lines`) and the gesture another node plays (`gesture`). Its nodes are each front-end's:
`demo_driver` (enables the node, prints what moves, disables it), `gesture_player` and `recorder_node` in
cssr_system.ros1 and cssr_system.ros2."""
