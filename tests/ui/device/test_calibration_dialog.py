"""The device panel's Calibrate…: "connect first" before anything is asked; each reading checked before it is
used (a fake charger's readings); and on the simulated iMAX B6 started uncalibrated, the user's readings (the
model's truth) entered as the dialog asks for them, the block stored."""
import threading

import pytest
from PySide6.QtCore import QObject, Signal

from b6_sim import B6_BAUD, uncalibrated_b6
from fake_b6_calibration import FakeB6, patch_calibrator
from zuml_studio.ui.device.calibration_dialog import CalibrationDialog
from zuml_studio.ui.device.connection import DeviceConnection

b6 = pytest.fixture(uncalibrated_b6)
CONNECT_FIRST = "Connect to the charger first (an iMAX B6 with the ZUML firmware)."


def test_the_panel_s_calibrate_says_connect_first_before_asking_anything(make_window, qtbot):
    w = make_window()
    panel = w.device_panel
    panel.calibrate_button.click()
    dialog = panel.findChild(CalibrationDialog)
    qtbot.waitUntil(dialog.isVisible)
    assert dialog.status.isVisible() and dialog.status.text() == CONNECT_FIRST
    assert not any(widget.isEnabled() for widget in (dialog.pack, dialog.supply, dialog.cells, dialog.reading,
                                                      dialog.use_reading, dialog.start_button))
    dialog.close()


class FakeConnection(QObject):
    """The panel's connection to FakeB6 (a 3S pack at 11.4 V, every current held as asked): jobs run on a
    thread as the real worker's do, their results come back on the GUI thread."""
    connected = Signal(object)
    disconnected = Signal(str)
    _finished = Signal(object, object)

    def __init__(self):
        super().__init__()
        self.on = False
        self.client = FakeB6()
        self._finished.connect(lambda callback, value: callback(value))

    def is_connected(self) -> bool:
        return self.on

    def call(self, job, on_done, on_error) -> int:
        def run():
            try:
                self._finished.emit(on_done, job(self.client, None))
            except Exception as exc:                # noqa: BLE001 - every failure goes back, as the real worker's
                self._finished.emit(on_error, exc)
        threading.Thread(target=run, daemon=True).start()
        return 1


@pytest.fixture
def fake_dialog(qtbot, monkeypatch):
    patch_calibrator(monkeypatch)
    connection = FakeConnection()
    dialog = CalibrationDialog(connection)
    qtbot.addWidget(dialog)
    dialog.show()
    return dialog, connection


def test_the_form_opens_when_the_charger_is_connected(fake_dialog):
    dialog, connection = fake_dialog
    assert dialog.status.text() == CONNECT_FIRST and not dialog.start_button.isEnabled()
    connection.on = True
    connection.connected.emit(None)
    assert dialog.status.isHidden() and dialog.start_button.isEnabled() and dialog.pack.isEnabled()
    connection.on = False
    connection.disconnected.emit("unplugged")
    assert dialog.status.text() == CONNECT_FIRST and not dialog.start_button.isEnabled()


def connected(fake_dialog):
    dialog, connection = fake_dialog
    connection.on = True
    connection.connected.emit(None)
    return dialog, connection


def test_a_pack_typed_ten_times_low_is_refused_in_volts(fake_dialog, qtbot):
    dialog, connection = connected(fake_dialog)
    dialog.pack.setValue(1.17)
    dialog.start_button.click()
    qtbot.waitUntil(lambda: not dialog.busy())
    assert dialog.log.toPlainText().splitlines()[-1] == (
        "Stopped: the pack: 1.17 V entered, but the charger reads 11.40 V at its output (more than 6 % apart): "
        "check the meter's reading")
    assert [name for name, _p in connection.client.asked] == ["CAL_READ"]


def test_an_empty_cell_is_refused_not_shifted(fake_dialog):
    dialog, connection = connected(fake_dialog)
    dialog.pack.setValue(11.4)
    dialog.cells.setText("3.8,,3.8")
    dialog.start_button.click()
    assert dialog.log.toPlainText() == "the cells: item 2 is empty: give every cell from cell 1 on"
    assert not dialog.busy() and connection.client.asked == []


def test_each_current_is_asked_on_an_empty_field_and_a_typo_is_refused_in_amps(fake_dialog, qtbot):
    dialog, connection = connected(fake_dialog)
    dialog.pack.setValue(11.4)
    dialog.start_button.click()
    qtbot.waitUntil(lambda: dialog.reading.isEnabled())
    assert dialog.reading.text() == "" and not dialog.use_reading.isEnabled()
    dialog.reading.setText("x")
    assert not dialog.use_reading.isEnabled()
    dialog.reading.setText("101,5")
    dialog.use_reading.click()
    qtbot.waitUntil(lambda: dialog.reading.isEnabled() and "1000 mA" in dialog.question.text())
    assert dialog.reading.text() == ""                 # not the previous step's 101.5
    dialog.reading.setText("333")
    dialog.use_reading.click()
    qtbot.waitUntil(lambda: not dialog.busy())
    assert dialog.log.toPlainText().splitlines()[-1] == (
        "Stopped: the ammeter: 0.333 A entered, but the charger reads 1.000 A charging (more than 16 % apart): "
        "check the meter's reading")
    assert "CAL_WRITE" not in [name for name, _p in connection.client.asked]
    assert connection.client.mode == 0 and dialog.reading.text() == ""


def test_calibrating_the_simulated_b6_from_the_dialog(b6, qtbot):
    connection = DeviceConnection()
    try:
        failed = []
        connection.connectFailed.connect(failed.append)
        connection.open(b6.port, B6_BAUD)
        qtbot.waitUntil(lambda: connection.is_connected() or bool(failed), timeout=60_000)
        assert not failed, failed
        dialog = CalibrationDialog(connection)
        qtbot.addWidget(dialog)
        dialog.pack.setValue(b6.truth("voltage_v"))
        dialog.cells.setText("4,x")
        dialog.start_button.click()
        assert dialog.log.toPlainText() == "the cells: 'x' is not a number of volts" and not dialog.busy()
        dialog.cells.setText("")
        dialog.start_button.click()
        for _current in range(4):
            qtbot.waitUntil(lambda: dialog.reading.isEnabled() or not dialog.busy(), timeout=120_000)
            assert dialog.busy(), (_current, dialog.log.toPlainText(), dialog.reading.isEnabled())
            assert dialog.reading.text() == ""
            dialog.reading.setText(f"{abs(b6.truth('current_a')) * 1000:.1f}")
            dialog.use_reading.click()
        qtbot.waitUntil(lambda: not dialog.busy(), timeout=120_000)
        log = dialog.log.toPlainText()
        assert "Calibrated and stored" in log, log
    finally:
        connection.shutdown()
