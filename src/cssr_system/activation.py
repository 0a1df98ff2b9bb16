"""The setActivation service contract: accepted requests and replies (SPEC section 1)."""
from typing import Optional

NODE_NAME = "animateBehaviour"
SERVICE_NAME = NODE_NAME + "/setActivation"  # relative: a namespace applies
SERVICE_PATH = "/" + SERVICE_NAME  # where it is when the node runs in the root namespace

ENABLED = "enabled"
DISABLED = "disabled"
ACCEPTED_STATES = (ENABLED, DISABLED)
REPLY_SUCCESS = "1"
REPLY_FAILURE = "0"


def parse_activation_state(requested: str) -> Optional[str]:
    """ENABLED or DISABLED for a valid request (blanks around it and letter case ignored), else None."""
    state = (requested or "").strip().lower()
    return state if state in ACCEPTED_STATES else None
