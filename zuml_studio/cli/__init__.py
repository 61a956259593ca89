"""The ``zuml`` command line: one module per group of commands, registered by ``main``.

At the top of the package order with ``ui``: it may import every package below (not ``ui``). No Qt."""
