"""The device panel's Calibrate…: on the simulated iMAX B6 started uncalibrated, the user's readings (the
model's truth) entered as the dialog asks for them, the block stored."""
import pytest

from b6_sim import B6_BAUD, uncalibrated_b6
from zuml_studio.ui.device.calibration_dialog import CalibrationDialog
from zuml_studio.ui.device.connection import DeviceConnection

b6 = pytest.fixture(uncalibrated_b6)


def test_the_panel_has_a_calibrate_button_that_needs_a_connection(make_window, qtbot):
    w = make_window()
    panel = w.device_panel
    panel.calibrate_button.click()
    dialog = panel.findChild(CalibrationDialog)
    qtbot.waitUntil(dialog.isVisible)
    dialog.pack.setValue(12.0)
    dialog.start_button.click()
    assert dialog.log.toPlainText() == "Connect to the charger first (an iMAX B6 with the ZUML firmware)."
    dialog.close()


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
        assert dialog.log.toPlainText() == "the cells: '4,x' is not a list of volts" and not dialog.busy()
        dialog.cells.setText("")
        dialog.start_button.click()
        for _current in range(4):
            qtbot.waitUntil(lambda: dialog.use_reading.isEnabled() or not dialog.busy(), timeout=120_000)
            assert dialog.busy(), (_current, dialog.log.toPlainText(), dialog.use_reading.isEnabled())
            dialog.reading.setValue(abs(b6.truth("current_a")) * 1000)
            dialog.use_reading.click()
        qtbot.waitUntil(lambda: not dialog.busy(), timeout=120_000)
        log = dialog.log.toPlainText()
        assert "Calibrated and stored" in log, log
    finally:
        connection.shutdown()
