"""One home for the engine's integer codes: end states, status codes, output slots.

Numba folds module-level integer constants into the compiled kernels, so the
names cost nothing at run time.  The dictionaries give the words that the
Python layer reports.
"""

# End states of one impact (docs/science.md, "End states").
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

# Slots of the row returned by ``kernel.impact_kernel`` (one impact).
OUT_EPS2 = 0  # Stronge's eps^2
OUT_DEPS2 = 1  # d eps^2 / d alpha
OUT_STATE = 2  # end state code
OUT_STATUS = 3  # status code
OUT_X_MAX = 4  # maximum compression (scaled)
OUT_X_END = 5  # compression at the end
OUT_V_END = 6  # velocity at the end
OUT_T_MAX = 7  # time of maximum compression
OUT_T_END = 8  # time of the end
OUT_STEPS = 9  # attempted steps, events included
OUT_NFEV = 10  # right-hand-side evaluations
OUT_E_N = 11  # Newton's kinematic e_N = separation speed / approach speed (0 without separation)
OUT_DE_N = 12  # d e_N / d alpha
N_OUT = 13

# Slots of the row returned by ``solver.solve_kernel`` / ``solver.solve_point`` (one alpha).
SOL_ALPHA = 0  # damping factor found
SOL_EPS = 1  # eps that alpha produces
SOL_STATE = 2  # end state code of the impact at alpha
SOL_STATUS = 3  # status code of the root-finder
SOL_IMPACTS = 4  # impacts integrated
SOL_STEPS = 5  # integrator steps, all impacts
SOL_X_MAX = 6  # maximum compression at alpha
SOL_X_END = 7  # end compression at alpha
SOL_NFEV = 8  # right-hand-side evaluations, all impacts
SOL_E_N = 9  # Newton's e_N that alpha produces
N_SOLVE_OUT = 10

# Slots of the row returned by ``boundary.boundary_kernel`` (one load).
BND_ALPHA = 0  # alpha on the separation boundary
BND_EPS = 1  # eps on the boundary
BND_STATUS = 2  # status code of the search
N_BND_OUT = 3

# Columns of the trajectory record filled by ``impact_kernel``: scaled t, x, v.
REC_T = 0
REC_X = 1
REC_V = 2
N_REC = 3
