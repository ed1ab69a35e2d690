"""Calibrate a contact law from a drop test (issue 28): ``calibrate.api.calibrate``."""
