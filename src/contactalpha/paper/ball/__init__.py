"""paper.ball."""
