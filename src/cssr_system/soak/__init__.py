"""`make soak` (doc/soak.md): hours of compressed use of the node on the simulated Pepper, and what they leave behind.
The schedule of churn, the sampling of /proc, the figures and their targets, the report: plain Python; the ROS I/O is
in the drivers, cssr_system.ros1.soak_driver and cssr_system.ros2.soak_driver."""
