"""The frozen bundle's windowed entry point (``zuml-studio``)."""
import sys

from zuml_studio.ui.app import main

sys.exit(main())
