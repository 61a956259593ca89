"""zuml_studio.device.zuml (issue 36: see docs/architecture.md)."""
