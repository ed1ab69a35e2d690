"""DEM users' tools: the species table for LAMMPS, the names other DEM codes use, whether the load matters.

``species`` (``species_table``), ``names`` (LIGGGHTS, Yade, MFIX-DEM, Chrono SMC conversions and
``reduced_mass``), ``load`` (``load_matters``); docs/dem.md walks through them.
"""
