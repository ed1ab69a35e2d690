"""Exports of the package's numerics for code that cannot call Python (one module per target)."""
