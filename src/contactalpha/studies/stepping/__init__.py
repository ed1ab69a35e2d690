"""Figures of restitution at an engine's step (docs/stepping.md).

Numerics in ``compute``, plots in ``figures``.
"""
