"""engine: the jitted impact integrator, the alpha solver and the exact table.

Importing the folder first keys numba's cache of every kernel on the package
sources it can depend on (``jitcache``), before any kernel is decorated.
"""

from .jitcache import install

install()
