"""Test set-up shared by the whole suite."""
import os
import tempfile

# Before any Qt import anywhere: the GUI tests render offscreen, with no display.
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
# The suite's expected texts are English whatever the machine's locale; tests of other languages
# set ZUML_LANG (or drop it and set LANG) themselves.
os.environ["ZUML_LANG"] = "en"
# Settings, recovery files and user macros of the tests never touch the user's own.
os.environ["ZUML_STUDIO_CONFIG_DIR"] = tempfile.mkdtemp(prefix="zuml-studio-tests-")
# Nor the user's pack logbook.
os.environ["ZUML_STUDIO_DATA_DIR"] = tempfile.mkdtemp(prefix="zuml-studio-tests-data-")

import before_workers  # noqa: E402
import pytest  # noqa: E402
from chargers import KINDS  # noqa: E402
from tools import INSTALL  # noqa: E402
from hypothesis import HealthCheck, settings  # noqa: E402

# Reproducible in CI: the same examples every run, no flaky deadlines on a loaded 2-core machine.
settings.register_profile("ci", derandomize=True, deadline=None, max_examples=200,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("dev", deadline=None, max_examples=200)
settings.load_profile("ci" if os.environ.get("CI") else os.environ.get("HYPOTHESIS_PROFILE", "dev"))


def _parallel(config) -> bool:
    """Whether pytest-xdist runs this session on workers (`./dev test`); True in the controller and the workers."""
    return hasattr(config, "workerinput") or bool(config.getoption("numprocesses", None))


@pytest.hookimpl(tryfirst=True)
def pytest_sessionstart(session):
    if _parallel(session.config) and not hasattr(session.config, "workerinput"):
        before_workers.prepare()


def pytest_terminal_summary(terminalreporter):
    """Name every firmware test that skipped, and the one command that installs what it lacked. Here, not in
    tests/firmware/: the pytest-xdist controller, which writes the summary, loads no conftest below this one."""
    skipped = [r for r in terminalreporter.stats.get("skipped", []) if "firmware" in r.nodeid]
    if not skipped:
        return
    terminalreporter.section("firmware tests skipped")
    for report in skipped:
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        terminalreporter.write_line(f"{report.nodeid}: {reason}")
    terminalreporter.write_line(f"to run them: {INSTALL}")


def pytest_collection_modifyitems(config, items):
    """On workers, the frozen bundle's build (marked slow: minutes) is handed out first: handed out last (xdist
    orders files by their number of tests), one worker would still be building it long after the other ended.
    ./dev test passes --no-loadscope-reorder so that this order is kept."""
    if _parallel(config):
        items.sort(key=lambda item: item.get_closest_marker("slow") is None)


@pytest.fixture
def make_charger():
    """make_charger(baud=None, tcp=False, **VirtualCharger kwargs) -> (device, port_or_url): a
    virtual charger served on a pty (or TCP), unpaced unless ``baud`` is given."""
    from zuml_studio.virtual.transport import serve_pty, serve_tcp
    from zuml_studio.virtual.virtual_charger import VirtualCharger

    made = []

    def make(baud=None, tcp=False, **kw):
        device = VirtualCharger(**kw)
        where, stop = serve_tcp(device, "127.0.0.1", 0, baud) if tcp else serve_pty(device, baud)
        made.append((device, stop))
        return device, where

    yield make
    for device, stop in made:
        stop()
        device.close()


@pytest.fixture(params=KINDS)
def any_charger(request, make_charger, tmp_path):
    """any_charger(**VirtualCharger kwargs) -> chargers.Charger: a virtual charger on a pty (the
    kwargs), then, as the second parameter, the firmware on simavr (`zuml firmware-sim`; the kwargs
    do not apply: its battery is its own, 3 cells 2000 mAh, and it holds no passport)."""
    from chargers import Charger, FirmwareSims
    sims = FirmwareSims(tmp_path)

    def make(**kw):
        if request.param == "virtual":
            kw.setdefault("speed", 20000)
            device, port = make_charger(**kw)
            return Charger("virtual", port, device)
        return Charger("firmware-sim", sims.start())

    yield make
    sims.stop()
