"""Issue 13: the closed form for alpha(eps, xi), fitted and judged in delivered restitution."""
