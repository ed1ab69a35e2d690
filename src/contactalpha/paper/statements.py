"""The paper's claims checked against our numbers: one statement type, one verdict vocabulary.

Every stage that checks what the paper says (Fig. 9, the bouncing ball of Sect. 6) returns a
list of ``Statement``: the claim in the paper's words, the criterion we test in ours, the
numbers we found, and a verdict.  A claim whose data are absent from a run (a panel or model
left out of the configuration) is listed as ``NOT_CHECKED``, never as holding.
"""

from dataclasses import dataclass

HOLDS = "holds"
PARTLY = "partly"
FAILS = "does not hold"
NOT_CHECKED = "not checked"
VERDICTS = (HOLDS, PARTLY, FAILS, NOT_CHECKED)


@dataclass(frozen=True)
class Statement:
    """A claim of the paper and what our numbers say about it.

    Attributes
    ----------
    claim : the paper's statement.
    criterion : what we test, in words.
    evidence : our numbers (or why the claim could not be checked).
    verdict : one of ``VERDICTS``.
    """

    claim: str
    criterion: str
    evidence: str
    verdict: str

    def __post_init__(self):
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict = {self.verdict!r} is not one of {VERDICTS}")


def verdict(flags):
    """Verdict over the cases a criterion names: HOLDS if all pass, PARTLY if some, FAILS if none.

    No cases at all is no evidence: ``NOT_CHECKED``.
    """
    flags = [bool(f) for f in flags]
    if not flags:
        return NOT_CHECKED
    if all(flags):
        return HOLDS
    return PARTLY if any(flags) else FAILS


def not_checked(claim, criterion, missing):
    """A statement whose data are absent from this run; ``missing`` says which."""
    return Statement(claim, criterion, f"not in this run: {missing}", NOT_CHECKED)


def statements_markdown(statements, title, notes=()):
    """The statements as a markdown table under ``title``, with a count of each verdict."""
    lines = [f"# {title}", ""]
    lines += [f"- {n}" for n in notes]
    if notes:
        lines.append("")
    lines += ["| # | statement (paper) | criterion | our numbers | verdict |", "|---|---|---|---|---|"]
    for i, s in enumerate(statements, 1):
        claim, criterion, evidence = (text.replace("|", "\\|") for text in (s.claim, s.criterion, s.evidence))
        lines.append(f"| {i} | {claim} | {criterion} | {evidence} | **{s.verdict}** |")
    counts = ", ".join(f"{sum(s.verdict == v for s in statements)} {v}" for v in VERDICTS)
    lines += ["", f"Of {len(statements)} statements: {counts}."]
    return "\n".join(lines) + "\n"
