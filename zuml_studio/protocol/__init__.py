"""zuml_studio.protocol (issue 36: see docs/architecture.md)."""
