"""ROS_DOMAIN_IDs for the ROS 2 tests. Each is claimed with a lock file held for as long as the claiming test process
lives, so that runs side by side on one machine (make test's lanes, a second distribution, a developer's own run)
never meet on a domain; the kernel releases a claim when its process ends. 100 and 101 are the demo tests' domains."""
import fcntl
import os
import tempfile

DOMAINS = range(1, 100)
_claims = []  # the open lock files: a claim lasts while its file is open


def claim_domain() -> int:
    """A domain that no other process of this machine has claimed."""
    for domain in DOMAINS:
        lock = open(os.path.join(tempfile.gettempdir(), "cssr_system-ros2-domain-%d.lock" % domain), "w")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:  # claimed by another process
            lock.close()
            continue
        _claims.append(lock)
        return domain
    raise RuntimeError("every ROS_DOMAIN_ID from 1 to 99 is claimed by another test process on this machine")
