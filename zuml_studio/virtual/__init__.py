"""zuml_studio.virtual (issue 36: see docs/architecture.md)."""
