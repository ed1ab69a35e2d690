"""Figures of restitution at an engine's step (docs/stepping.md): numerics in ``compute``, plots in ``figures``."""
