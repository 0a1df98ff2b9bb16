"""Pepper's figure: forward kinematics, a body of simple solids, clearances and the animated GIF (doc/figure.md)."""
