"""The restitutions a law inverts, and their check."""

RESTITUTIONS = ("energetic", "kinematic")


def check_restitution(restitution):
    """``restitution`` if it names one of ``RESTITUTIONS``; else a ``ValueError`` naming them."""
    if restitution not in RESTITUTIONS:
        raise ValueError(f"restitution = {restitution!r} is not one of {', '.join(map(repr, RESTITUTIONS))}")
    return restitution


# How each restitution is written in messages and keywords.
TARGET_NAMES = {"energetic": "eps", "kinematic": "e_N"}


def target_name(restitution):
    """``"eps"`` (Stronge's energetic) or ``"e_N"`` (Newton's kinematic): the target's name in messages."""
    return TARGET_NAMES[check_restitution(restitution)]
