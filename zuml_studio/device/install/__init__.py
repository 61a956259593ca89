"""zuml_studio.device.install (issue 36: see docs/architecture.md)."""
