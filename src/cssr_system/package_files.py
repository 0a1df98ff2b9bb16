"""Where the package's files are: the one lookup that every program, tool and test uses.

ROS's package index comes first (ROS 1's rospkg; ROS 2's ament index where ROS_VERSION is 2, as ROS 2's setup
files set it), so a program run from an install space finds ``<install>/share/cssr_system`` (its ``config/``,
``data/``, ``launch/`` and ``package.xml``), and one run from a ROS 1 development workspace finds the source folder.
Where ROS does not know the package (e.g. a plain ``pytest`` run), the source tree around this module is used.
"""
import functools
import os
import xml.etree.ElementTree as ElementTree

PACKAGE_NAME = "cssr_system"
_SOURCE_TREE = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


class PackageNotFound(RuntimeError):
    pass


@functools.lru_cache(maxsize=None)
def package_dir() -> str:
    """The package's folder: the one holding package.xml, config/, data/ and launch/."""
    try:
        return _indexed_package_dir()
    except Exception:  # no ROS index, or the package not in it
        if os.path.isfile(os.path.join(_SOURCE_TREE, "package.xml")):
            return _SOURCE_TREE
        raise PackageNotFound("cannot find the package %s: ROS does not know it (source the workspace's "
                              "setup.bash) and %s holds no package.xml" % (PACKAGE_NAME, _SOURCE_TREE))


def _indexed_package_dir() -> str:
    # Imported here, not at the top: the plotting tool works without ROS, and each ROS has only its own index.
    if os.environ.get("ROS_VERSION") == "2":
        from ament_index_python.packages import get_package_share_directory
        return get_package_share_directory(PACKAGE_NAME)
    import rospkg
    return rospkg.RosPack().get_path(PACKAGE_NAME)


def package_path(*parts: str) -> str:
    """A path inside the package, e.g. package_path("config", "animateBehaviourConfiguration.ini")."""
    return os.path.join(package_dir(), *parts)


def data_dir() -> str:
    """The package's ``data/`` folder: topic files, and the default place of the log file."""
    return package_path("data")


def package_version() -> str:
    """The version in package.xml, or "unknown" when it cannot be read."""
    try:
        return ElementTree.parse(package_path("package.xml")).getroot().findtext("version") or "unknown"
    except (OSError, ElementTree.ParseError, PackageNotFound):
        return "unknown"
