"""paper.surface."""
