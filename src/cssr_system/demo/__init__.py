"""The demo (`make demo`, launch/animateBehaviourDemo.launch): its driver node, which enables the node,
prints what moves and disables it (`driver`), the gesture player that sends a gesture as another node
would (`gesture_player`), and their pure parts (`live_lines`, `gesture`). The recorder that writes the
recording and its plot is in `cssr_system.animate_behaviour.recording.recorder_node`."""
