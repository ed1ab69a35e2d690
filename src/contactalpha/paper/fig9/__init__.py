"""paper.fig9."""
