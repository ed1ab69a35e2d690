"""One home for the engine's integer codes: end states, status codes, output slots.

Numba folds module-level integer constants into the compiled kernels, so the
names cost nothing at run time.  The dictionaries give the words that the
Python layer reports.
"""

# End states of one impact (docs/science.md, "How an impact ends").
FAILED = 0
SEPARATION = 1
NONSEPARATION = 2
CREEP = 3
NO_RESTITUTION = 4
END_STATES = {
    FAILED: "failed",
    SEPARATION: "separation",
    NONSEPARATION: "nonseparation",
    CREEP: "creep",
    NO_RESTITUTION: "no_restitution",
}
STATE_CODES = {name: code for code, name in END_STATES.items()}

# Status codes shared by every kernel and by the alpha solver.
OK = 0
STEP_LIMIT = 1
STEP_UNDERFLOW = 2
NON_FINITE = 3
EVENT_FAILED = 4
NO_BRACKET = 5
NOT_CONVERGED = 6
STATUS = {
    OK: "ok",
    STEP_LIMIT: "step limit exceeded",
    STEP_UNDERFLOW: "step size underflow",
    NON_FINITE: "non-finite state",
    EVENT_FAILED: "event location failed",
    NO_BRACKET: "no root bracketed",
    NOT_CONVERGED: "root tolerance not reached",
}
