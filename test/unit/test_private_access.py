"""No module of the package reaches into the private parts of rospy, actionlib or genpy, except
src/cssr_system/ros1/rospy_compat.py, which says why for each (README: "Package layout")."""
import pathlib
import re

SOURCE = pathlib.Path(__file__).resolve().parents[2] / "src" / "cssr_system"
COMPAT = SOURCE / "ros1" / "rospy_compat.py"
# A private attribute of another object (`x._name`, not our own `self._name`), rospy's implementation objects
# (`.impl`), and a connection's socket.
PRIVATE = re.compile(r"(?<!self)(?<!cls)\.(_[a-z][A-Za-z0-9_]*)\b|\.impl\b|\.socket\b|_connection_header|_buff\b")
# Names of our own that start with an underscore and are used across objects of ours: none are allowed either,
# except those the standard library documents (os._exit, sys._getframe are not used).
ALLOWED = {"os._exit", "_replace", "_asdict", "_fields"}


def private_uses(lines, where=""):
    for number, line in enumerate(lines, 1):
        code = line.split("#", 1)[0]
        for match in PRIVATE.finditer(code):
            name = match.group(1) or match.group(0)
            if name.lstrip(".") in ALLOWED or ("os." + name) in ALLOWED:
                continue
            yield "%s:%d: %s" % (where, number, line.strip())


def test_private_parts_are_used_only_in_the_compat_module():
    found = [use for path in sorted(SOURCE.rglob("*.py")) if path != COMPAT
             for use in private_uses(path.read_text().splitlines(), path.relative_to(SOURCE))]
    assert found == []


def test_the_check_finds_what_it_looks_for():
    assert len(list(private_uses(COMPAT.read_text().splitlines()))) >= 3, "the compat module's own uses are found"
    caught = ["publisher.impl.set_queue_size(None)", "message._buff", "connection.socket.setsockopt(1, 2, 3)",
              "rospy.core._shutdown_flag", "getattr(message, '_connection_header', {})"]
    assert all(list(private_uses([line])) for line in caught)
    allowed = ["self._lock = None", "point._replace(time=1.0)", "os._exit(status)", "cls._instances = {}"]
    assert not any(list(private_uses([line])) for line in allowed)
