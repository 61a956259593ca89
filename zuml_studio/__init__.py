"""ZUML Studio."""
