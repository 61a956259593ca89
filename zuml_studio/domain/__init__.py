"""The concepts every other package shares, at the bottom of the package order: chemistries and their
limits, start templates, the telemetry sample, phase and event records, end reasons, units, and the one
root of the package's errors. It imports nothing of ZUML Studio's above it (see docs/architecture.md)."""
