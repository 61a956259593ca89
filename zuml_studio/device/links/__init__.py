"""zuml_studio.device.links (issue 36: see docs/architecture.md)."""
