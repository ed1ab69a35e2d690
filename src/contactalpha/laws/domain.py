"""The restitutions a law inverts (their check is ``contactalpha.validation.check_restitution``)."""

from contactalpha.validation import RESTITUTIONS, check_restitution

__all__ = ["RESTITUTIONS", "TARGET_NAMES", "check_restitution", "target_name"]


# How each restitution is written in messages and keywords.
TARGET_NAMES = {"energetic": "eps", "kinematic": "e_N"}


def target_name(restitution):
    """``"eps"`` (Stronge's energetic) or ``"e_N"`` (Newton's kinematic): the target's name in messages."""
    return TARGET_NAMES[check_restitution(restitution)]
