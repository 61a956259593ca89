"""The ``zuml`` command line."""
