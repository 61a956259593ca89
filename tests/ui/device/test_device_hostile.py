"""The Device panel against hostile bytes and a failing disk (issue 12, points 5 and 6)."""
import csv
import errno
import os

import pytest

from device_helpers import WAIT_MS, connect
from helpers import lose_link_after_commit

pytestmark = pytest.mark.skipif(os.name != "posix", reason="the virtual chargers use ptys here")


class FullDisk:
    """A file whose every write and flush fails as on a full disk."""
    closed = False

    def write(self, data):
        raise OSError(errno.ENOSPC, "No space left on device")

    flush = write

    def close(self):
        self.closed = True


def test_passport_control_bytes_are_shown_escaped_and_flagged(qtbot, make_panel):
    panel = make_panel()
    connect(qtbot, panel)
    panel.connection.virtual_device.chip._image[0x04:0x0C] = b"<b>\x1b[2J\r"
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS):
        panel.refresh_passport()
    label = panel.pp_labels["serial"]
    assert label.text().startswith("ZU<b>\\x1b[2J\\x0d") and label.text().endswith("⚠")
    assert "non-printable" in label.toolTip()


def test_a_session_csv_write_failure_is_said_once_and_the_plot_goes_on(qtbot, make_panel):
    panel = make_panel()
    connect(qtbot, panel)
    log = panel.session.log
    log.idle_s = 0.0            # every idle frame written: the failure comes at once
    log._fh = FullDisk()
    log._writer = csv.writer(log._fh)
    qtbot.waitUntil(lambda: "No space left on device" in panel.message_text(), timeout=WAIT_MS)
    assert panel.message_text().startswith("Session CSV: cannot write")
    before = panel.series.last_telemetry
    qtbot.waitUntil(lambda: panel.series.last_telemetry is not before, timeout=WAIT_MS)   # telemetry goes on
    panel.disconnect()
    qtbot.waitUntil(lambda: not panel.is_connected(), timeout=WAIT_MS)
    assert "⚠ cannot write" in panel.session_label.full_text()


def test_a_flash_whose_verify_was_lost_is_settled_by_the_next_read(qtbot, make_panel, monkeypatch):
    panel = make_panel()
    connect(qtbot, panel)
    lose_link_after_commit(monkeypatch)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    ok, text = flashed.args
    assert not ok and text.startswith("The charger confirmed the new image, then the connection was lost")
    assert "nothing was written" not in text
    # still connected here, so the panel reads the slots at once: that settles it
    qtbot.waitUntil(lambda: panel.message_text().startswith("Read back after the lost link: the flash is on "
                                                            "the charger, verified."), timeout=WAIT_MS)
    assert panel.slot_names() == ["NiMh-dV"]


def test_a_lost_write_is_not_settled_by_another_device_on_the_port(qtbot, make_panel, monkeypatch):
    """Issue 27: a port that vanished may come back as another device, whose EEPROM says nothing about
    the lost write. Told apart by IDENTIFY: here the write went to a charger of another model."""
    import dataclasses

    from zuml_studio.ui.device.charger_slots import ChargerSlots
    real = ChargerSlots._note_unsettled

    def written_elsewhere(self, what, exc):
        real(self, what, exc)
        if self._unsettled is not None:
            what, exc, info = self._unsettled
            self._unsettled = (what, exc, dataclasses.replace(info, model="Charger-Written-To"))
    monkeypatch.setattr(ChargerSlots, "_note_unsettled", written_elsewhere)
    panel = make_panel()
    connect(qtbot, panel)
    lose_link_after_commit(monkeypatch)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS):
        panel.flash()
    qtbot.waitUntil(lambda: panel.message_text().startswith("Another device answers on this port now"),
                    timeout=WAIT_MS)
    assert "not the Charger-Written-To" in panel.message_text()


def test_a_lost_write_is_not_verified_on_a_twin_that_does_not_know_its_token(qtbot, make_panel, monkeypatch):
    """Issue 34: a second charger of the same model and firmware, holding the same image, answers IDENTIFY
    alike. Only the unit that committed the write knows its token (the host's nonce): here the charger read
    does not (the token noted is another), so the new image it holds is not verified."""
    from zuml_studio.ui.device.charger_slots import ChargerSlots
    real = ChargerSlots._note_unsettled

    def twin(self, what, exc):
        real(self, what, exc)
        if self._unsettled is not None:
            exc.token ^= 0x5A5A5A5A                  # the write this charger never saw
    monkeypatch.setattr(ChargerSlots, "_note_unsettled", twin)
    panel = make_panel()
    connect(qtbot, panel)
    lose_link_after_commit(monkeypatch)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS):
        panel.flash()
    qtbot.waitUntil(lambda: "not verified to be the one written to" in panel.message_text(), timeout=WAIT_MS)
    assert panel.slot_names() == ["NiMh-dV"]
