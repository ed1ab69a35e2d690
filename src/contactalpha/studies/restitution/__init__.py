"""Newton's kinematic e_N against Stronge's energetic eps under a load (issue 11, part 1)."""
