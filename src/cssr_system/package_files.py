"""Where the package's files are: the one lookup that every program, tool and test uses.

ROS's package index comes first, read as each ROS's setup files leave it in the environment, so that this module
imports no ROS (the core below both front-ends uses it): on ROS 2 (ROS_VERSION 2) the ament index of
AMENT_PREFIX_PATH, whose ``share/ament_index/resource_index/packages/cssr_system`` marks ``<prefix>/share/cssr_system``;
on ROS 1 the folders of ROS_PACKAGE_PATH, searched as rospack searches them (the first folder holding the package's
package.xml, not below another package). So a program run from an install space finds ``<install>/share/cssr_system``
(its ``config/``, ``data/``, ``launch/`` and ``package.xml``), and one run from a ROS 1 development workspace finds
the source folder. Where ROS does not know the package (e.g. a plain ``pytest`` run), the source tree around this
module is used.
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
    if os.environ.get("ROS_VERSION") == "2":
        return _ament_package_dir(os.environ.get("AMENT_PREFIX_PATH", ""))
    return _ros_package_path_dir(os.environ.get("ROS_PACKAGE_PATH", ""))


def _ament_package_dir(prefixes: str) -> str:
    for prefix in filter(None, prefixes.split(os.pathsep)):
        if os.path.isfile(os.path.join(prefix, "share", "ament_index", "resource_index", "packages", PACKAGE_NAME)):
            return os.path.join(prefix, "share", PACKAGE_NAME)
    raise PackageNotFound("%s is not in the ament index of AMENT_PREFIX_PATH" % PACKAGE_NAME)


def _ros_package_path_dir(folders: str) -> str:
    for folder in filter(None, folders.split(os.pathsep)):
        found = _package_below(folder)
        if found:
            return found
    raise PackageNotFound("%s is in no folder of ROS_PACKAGE_PATH" % PACKAGE_NAME)


def _package_below(folder: str) -> str:
    """The folder at or below `folder` whose package.xml names the package ("" if none). As rospack does, a folder
    with a package.xml is a package whose subfolders are not searched, nor are hidden folders or those marked
    CATKIN_IGNORE."""
    for here, subfolders, names in os.walk(folder, followlinks=True):
        if "package.xml" in names:
            subfolders.clear()
            if _package_name(os.path.join(here, "package.xml")) == PACKAGE_NAME:
                return here
        elif "CATKIN_IGNORE" in names:
            subfolders.clear()
        subfolders[:] = [name for name in subfolders if not name.startswith(".")]
    return ""


def _package_name(manifest: str) -> str:
    try:
        return ElementTree.parse(manifest).getroot().findtext("name") or ""
    except (OSError, ElementTree.ParseError):
        return ""


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
