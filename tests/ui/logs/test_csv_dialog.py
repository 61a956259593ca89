"""The CSV import in the log viewer: the guess shown in a dialog, corrected there, remembered per
header (the SkyRC B6AC v2 logger's real CSVs, tests/data/realdata, logged with positive current
while discharging)."""
import csv
import shutil
from pathlib import Path

import pytest
from PySide6.QtCore import QSettings

from zuml_studio.ui.logs import LogWindow
from zuml_studio.ui.logs.csv_dialog import CsvDialog

REAL = Path(__file__).resolve().parents[2] / "data" / "realdata"
READ_MS = 30_000


@pytest.fixture
def window(qtbot, tmp_path):
    w = LogWindow(QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat))
    qtbot.addWidget(w)
    w.resize(1366, 768)
    w.show()
    return w


def open_log(window, qtbot, path):
    with qtbot.waitSignal(window.documentOpened, timeout=READ_MS) as blocker:
        window.open_path(str(path))
    return blocker.args[0]


def test_the_guess_is_shown_corrected_and_remembered_for_the_header(window, qtbot, tmp_path):
    src = REAL / "skyrc_B6ACv2_Discharging_head100.csv"
    with src.open() as fh:
        body = list(csv.reader(fh))[1:]
    document = open_log(window, qtbot, src)
    # As guessed: the logger's discharge current is positive, its voltage falls under load: a discharge.
    assert document.log.samples[-1].current_a == pytest.approx(-float(body[-1][2]) / 1000)
    dialog = window.csv_dialog
    assert isinstance(dialog, CsvDialog) and dialog.isVisible()
    assert dialog.spec() == "time:s,voltage:V,current:mA,charge:mAh"
    assert dialog.table.item(1, 0).text() == "Volatge" and dialog.table.item(1, 3).text() == body[0][1]
    dialog.units[2].setCurrentIndex(dialog.units[2].findData("-mA"))    # the logger's discharge is positive
    with qtbot.waitSignal(window.documentOpened, timeout=READ_MS) as blocker:
        dialog.accept_button().click()
    corrected = blocker.args[0]
    assert window.tabs.count() == 1
    assert corrected.log.samples[-1].current_a == pytest.approx(-float(body[-1][2]) / 1000)
    # integrated; the logger's 1 mAh counter agrees
    assert corrected.log.samples[-1].mah_out == pytest.approx(float(body[-1][3]) - float(body[0][3]), abs=1.0)
    # another file with the same header: read with the remembered columns, no dialog this time
    window.csv_dialog = None
    other = tmp_path / "again.csv"
    shutil.copy(src, other)
    again = open_log(window, qtbot, other)
    assert again.log.meta["csv_columns"] == "time:s,voltage:V,current:-mA,charge:mAh"
    assert window.csv_dialog is None


def test_a_csv_whose_columns_cannot_be_guessed_asks_for_them(window, qtbot, tmp_path):
    path = tmp_path / "cycler.csv"
    path.write_text("a;b;c\n" + "".join(f"{k};{3.5 + k / 100:.2f};1,0\n" for k in range(30)))
    window.open_path(str(path))
    qtbot.waitUntil(lambda: window.csv_dialog is not None and window.csv_dialog.isVisible(), timeout=READ_MS)
    dialog = window.csv_dialog
    dialog.roles[1].setCurrentIndex(dialog.roles[1].findData("voltage"))
    dialog.roles[0].setCurrentIndex(dialog.roles[0].findData("time"))
    dialog.units[0].setCurrentIndex(dialog.units[0].findData("min"))
    with qtbot.waitSignal(window.documentOpened, timeout=READ_MS) as blocker:
        dialog.accept_button().click()
    log = blocker.args[0].log
    assert len(log.samples) == 30 and log.samples[-1].time_s == 29 * 60 and log.samples[-1].voltage_v == 3.79


def test_a_choice_without_voltage_is_refused_in_the_dialog(window, qtbot):
    open_log(window, qtbot, REAL / "skyrc_B6ACv2_Charging_head100.csv")
    dialog = window.csv_dialog
    dialog.roles[1].setCurrentIndex(dialog.roles[1].findData("-"))
    dialog.accept_button().click()
    assert dialog.isVisible() and "no voltage column" in dialog.error.text()


def test_the_dialog_says_which_units_were_assumed(window, qtbot):
    # The SkyRC logger's header gives no unit: "Current" 310 is read as mA, and the dialog says so.
    open_log(window, qtbot, REAL / "skyrc_B6ACv2_Charging_head100.csv")
    about = window.csv_dialog.findChild(type(window.csv_dialog.error), "csvAbout").text()
    assert "Units the header does not give (check them):" in about
    assert "  Current: no unit in the header: read as mA (largest value" in about
