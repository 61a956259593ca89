"""The frozen bundle's console entry point (``zuml``)."""
import sys

from zuml_studio.cli.main import main

sys.exit(main())
