"""The frozen bundle's console entry point (``zuml``)."""
import multiprocessing
import sys

# First: a child of the simulator panel's fork server (or of spawn) runs this same executable, which
# must then be that child, not a second application (PyInstaller's hook answers here).
multiprocessing.freeze_support()

from zuml_studio.cli.main import main

sys.exit(main())
