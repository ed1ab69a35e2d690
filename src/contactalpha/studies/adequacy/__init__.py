"""Which model a scene needs: adequacy maps over (eps, xi), the physical bounce threshold, rest prediction."""
