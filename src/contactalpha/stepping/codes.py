"""One home for the stepping kernels' integer codes: drop status and output slots.

Numba folds these module-level integers into the kernels; the dictionaries give the words the
Python layer reports.
"""

# Status of one drop (``drop.run_drop``) or one phase mean (``phase.phase_mean``).
SEPARATED = 0  # the body left the contact: e_N read from the free flight after it
CAPTURED = 1  # the body came to rest in contact: e_N = 0 (Newton), eps from the energy
STEP_LIMIT = 2  # max_steps ran out with the body still moving in contact: NaN
NON_FINITE = 3  # the state stopped being finite (an unstable step): NaN
QUAD_LIMIT = 4  # the phase quadrature ran out of intervals before its tolerance: estimate kept
DROP_STATUS = {
    SEPARATED: "separated",
    CAPTURED: "captured",
    STEP_LIMIT: "step limit exceeded",
    NON_FINITE: "non-finite state",
    QUAD_LIMIT: "quadrature interval limit",
}

# Slots of the row ``drop.run_drop`` returns (one drop).
D_EN = 0  # Newton's e_N (0 when captured)
D_EPS = 1  # Stronge's eps from the energy identity with the deepest sampled penetration
D_STEPS = 2  # steps that started in contact (from touchdown to separation or rest)
D_DMAX = 3  # deepest sampled penetration, m
D_STATUS = 4  # status code
N_DROP = 5

# Slots of the row ``phase.phase_mean`` returns (one scene, all phases).
P_MEAN = 0  # mean e_N over a uniform touchdown phase
P_MIN = 1  # smallest e_N one drop sees (over the evaluated phases, jumps' sides included)
P_MAX = 2  # largest e_N
P_STD = 3  # standard deviation of e_N over the phase
P_EPS_MEAN = 4  # mean of Stronge's eps
P_EPS_MIN = 5
P_EPS_MAX = 6
P_EPS_STD = 7
P_STEPS_MIN = 8  # fewest steps in contact over the phase
P_STEPS_MAX = 9  # most steps in contact
P_ERR = 10  # estimated quadrature error of the mean (e_N and eps, the larger)
P_JUMPS = 11  # jumps located (phases where the steps in contact change)
P_EVALS = 12  # drops evaluated
P_STATUS = 13  # worst status over the evaluated drops (or QUAD_LIMIT)
N_PHASE = 14
