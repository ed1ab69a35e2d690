"""paper.bench."""
