"""paper.fit."""
