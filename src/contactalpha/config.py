"""Checks on the workflow configuration that its JSON schema cannot express.

The Snakefile calls ``check_config`` right after the schema validation, so a
bad grid fails before any job runs, with a message naming the key.
"""

from contactalpha.paper.surface.compute import check_surface_config

# Section name -> check; stages add theirs here.
SECTION_CHECKS = {"surface": check_surface_config}


def check_config(config):
    """Raise ``ValueError`` naming the first bad key of the workflow ``config`` (a dict)."""
    for name, check in SECTION_CHECKS.items():
        if name in config:
            check(config[name], key=name)
