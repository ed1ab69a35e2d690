"""Calibrate a contact law from a drop test (issue 28); the entry point is ``contactalpha.calibrate``."""
