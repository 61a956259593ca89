"""zuml_studio.streams (issue 36: see docs/architecture.md)."""
