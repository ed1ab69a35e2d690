"""The restitutions a law inverts, and their check."""

RESTITUTIONS = ("energetic", "kinematic")


def check_restitution(restitution):
    """``restitution`` if it names one of ``RESTITUTIONS``; else a ``ValueError`` naming them."""
    if restitution not in RESTITUTIONS:
        raise ValueError(f"restitution = {restitution!r} is not one of {', '.join(map(repr, RESTITUTIONS))}")
    return restitution
