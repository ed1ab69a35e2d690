"""Round trips of our alpha inside real multibody engines (issue 11, part 3)."""
