"""Stages beyond the paper: one subfolder per stage."""
