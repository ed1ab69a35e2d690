"""The commit that results record: the hash, ``+dirty`` for a modified checkout, ``unknown`` outside git."""

import re
import subprocess
from datetime import UTC, datetime

from contactalpha.provenance import git_commit, history_line
from contactalpha.version import __version__


def git(repo, *args):
    done = subprocess.run(["git", *args], cwd=repo, capture_output=True, text=True, check=True)
    return done.stdout.strip()


def test_git_commit_is_head_then_dirty_after_an_edit_of_a_tracked_file(tmp_path):
    git(tmp_path, "init", "-q")
    (tmp_path / "code.py").write_text("X = 1\n")
    git(tmp_path, "add", "code.py")
    git(tmp_path, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "first")
    head = git(tmp_path, "rev-parse", "HEAD")
    assert re.fullmatch(r"[0-9a-f]{40}", head)
    assert git_commit(tmp_path) == head
    (tmp_path / "scratch.txt").write_text("untracked files do not change the code\n")
    assert git_commit(tmp_path) == head
    (tmp_path / "code.py").write_text("X = 2\n")
    assert git_commit(tmp_path) == head + "+dirty"
    git(tmp_path, "add", "code.py")  # staged but not committed: still not the commit's code
    assert git_commit(tmp_path) == head + "+dirty"
    git(tmp_path, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "second")
    second = git(tmp_path, "rev-parse", "HEAD")
    assert second != head and git_commit(tmp_path) == second


def test_git_commit_outside_a_repository_is_unknown(tmp_path):
    assert git_commit(tmp_path) == "unknown"


def test_history_line_is_the_utc_time_now_the_step_and_the_version():
    before = datetime.now(UTC).replace(microsecond=0)
    stamp, rest = history_line("merge of 2 chunks").split(" ", 1)
    after = datetime.now(UTC)
    assert before <= datetime.strptime(stamp, "%Y-%m-%dT%H:%M:%SZ").replace(tzinfo=UTC) <= after
    assert rest == f"merge of 2 chunks (contactalpha {__version__})"
