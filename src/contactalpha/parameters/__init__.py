"""The front door: ``contact_parameters``, from a scene in SI units to every number an engine needs.

One module per path: ``front_door`` checks the call and picks the path; ``one_scene`` solves one
scene for the continuous law (Hunt-Crossley through the shipped table, every other law through
its inverse); ``batch`` arrays of scenes; ``at_step`` one scene at an engine's step and
``at_step_batch`` a batch there; ``verify`` runs the installed engine.  ``result`` is the one
answer type; ``reach`` names what a target no damping reaches would need; ``engine_block`` is the
answer of ``contactalpha params --engine``.  The physics of a ball under a load (its bounces, the
separation threshold, the advice) stays in ``contactalpha.scene``, below this folder.
"""
