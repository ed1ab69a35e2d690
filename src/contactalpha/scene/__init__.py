"""The physics of a ball under a constant load: its drop, bounces, separation threshold and advice.

``ball`` (the bouncing ball and its numerics), ``bounces`` (the bounce sequence), ``threshold``
(the critical speed below which an impact no longer separates), ``advisor`` (which damping model a
scene needs), ``hertz`` (Hertz's stiffness), ``load`` (the load as ``accel`` or ``force``) and
``law_scene`` (the same answers for the other contact laws).  The front door,
``contact_parameters``, is above this folder, in ``contactalpha.parameters``.
"""
