"""Study: what the engines' usual restitution mappings deliver under a load, law by law."""
