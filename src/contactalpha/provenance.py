"""Provenance of every result: package version, git commit, time-stamped history lines."""

import subprocess
from datetime import UTC, datetime
from pathlib import Path

from contactalpha.version import __version__


def git_commit(path=None):
    """Commit hash of the checkout at ``path`` (``+dirty`` if modified), or ``unknown``."""
    cwd = Path(path or Path(__file__).parent)
    try:
        head = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=cwd, capture_output=True, text=True, check=True, timeout=10
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=cwd,
            capture_output=True,
            text=True,
            check=True,
            timeout=10,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head + ("+dirty" if dirty else "")


def history_line(step):
    """One ``history`` entry: UTC time stamp, the step, the package version."""
    stamp = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    return f"{stamp} {step} (contactalpha {__version__})"
