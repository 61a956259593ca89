"""Test set-up shared by the whole suite."""
import os
import tempfile

# Before any Qt import anywhere: the GUI tests render offscreen, with no display.
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
# Settings, recovery files and user macros of the tests never touch the user's own.
os.environ["ZUML_STUDIO_CONFIG_DIR"] = tempfile.mkdtemp(prefix="zuml-studio-tests-")

from hypothesis import HealthCheck, settings  # noqa: E402

# Reproducible in CI: the same examples every run, no flaky deadlines on a loaded 2-core machine.
settings.register_profile("ci", derandomize=True, deadline=None, max_examples=200,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("dev", deadline=None, max_examples=200)
settings.load_profile("ci" if os.environ.get("CI") else os.environ.get("HYPOTHESIS_PROFILE", "dev"))
