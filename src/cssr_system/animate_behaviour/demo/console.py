"""What the demo's nodes (the driver, the gesture player, the recorder) print for the person running it."""


def say(node_name: str, text: str) -> None:
    """One line, ``<node_name>: <text>``, printed at once (under roslaunch stdout is a pipe, which would hold it
    back)."""
    print("%s: %s" % (node_name, text), flush=True)
