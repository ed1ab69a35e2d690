"""Impulse engines (a rigid contact with a restitution coefficient): their step as a map, the inverse."""
