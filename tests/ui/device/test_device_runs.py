"""Issue 15 (3, 4, 5, 6): Restore asks, naming what is lost; Backup starts in the documents
folder; the virtual battery "from the macro" takes its cells and capacity and says so; Start
is off while a run goes on; each Start is a new plotted run, earlier ones kept; the flash
progress bar shows a finished flash."""
from pathlib import Path

from PySide6.QtWidgets import QFileDialog

from device_helpers import WAIT_MS, connect, flash_and_start
from helpers import compiled, seed_text

LIPO_3S = seed_text("LiPo").replace("  AKK_TYPE=LiPo\n", "  AKK_TYPE=LiPo\n  SERIES=3\n  CAPACITY=2200\n")


def _flash(qtbot, panel):
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    assert flashed.args[0], flashed.args[1]


def test_restore_asks_first_naming_the_macros_it_would_lose(qtbot, make_panel, editor, tmp_path, monkeypatch):
    from zuml_studio.ui.device import confirm_dialogs
    panel = make_panel()
    connect(qtbot, panel)
    _flash(qtbot, panel)
    backup = tmp_path / "backup.bin"
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS):
        panel.backup(backup)
    editor.set("LiPo")
    _flash(qtbot, panel)
    assert panel.slot_names() == ["NiMh-dV", "LiPo"]
    asked = []
    monkeypatch.setattr(confirm_dialogs, "confirm_restore", lambda parent, text: asked.append(text) or False)
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *a, **k: (str(backup), ""))
    panel.restore_button.click()
    assert len(asked) == 1
    assert "It replaces the 2 macros on the charger: NiMh-dV, LiPo." in asked[0]
    assert "Lost (not in the image): LiPo." in asked[0]
    assert panel.message_text().startswith("Not restored")
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS):
        panel.refresh_slots()
    assert panel.slot_names() == ["NiMh-dV", "LiPo"]


def test_backup_and_restore_start_in_the_documents_folder_named_by_charger_and_day(qtbot, make_panel, monkeypatch,
                                                                                     tmp_path):
    from datetime import date

    from zuml_studio.ui.device.confirm_dialogs import documents_folder
    monkeypatch.setenv("HOME", str(tmp_path))
    (tmp_path / "Documents").mkdir()
    panel = make_panel()
    connect(qtbot, panel)
    seen = []
    monkeypatch.setattr(QFileDialog, "getSaveFileName", lambda *a, **k: seen.append(a[2]) or ("", ""))
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *a, **k: seen.append(a[2]) or ("", ""))
    panel.backup_button.clicked.emit()
    panel.restore_button.clicked.emit()
    suggested = Path(seen[0])
    assert suggested.parent == tmp_path / "Documents" and Path(documents_folder()) == tmp_path / "Documents"
    assert suggested.name == f"iMAX-B6-virtual-{date.today().isoformat()}.bin"      # the virtual charger's model
    assert seen[1] == documents_folder()


def test_a_backup_name_is_the_charger_and_the_day_in_characters_every_file_system_takes():
    from datetime import date

    from zuml_studio.ui.device.charger_slots import backup_name
    day = date(2026, 12, 3)
    assert backup_name("iMAX B6 (virtual)", day) == "iMAX-B6-virtual-2026-12-03.bin"
    assert backup_name("a/b:c", day) == "a-b-c-2026-12-03.bin"
    assert backup_name("", day) == "charger-2026-12-03.bin"


def test_without_a_documents_folder_backup_starts_at_home_never_in_a_hidden_folder(monkeypatch, tmp_path):
    from zuml_studio.ui.device.confirm_dialogs import documents_folder
    monkeypatch.setenv("HOME", str(tmp_path))
    assert documents_folder() == str(tmp_path)


def test_the_virtual_battery_from_the_macro_takes_its_cells_and_capacity_and_says_so(make_panel, editor):
    editor.value = (compiled(LIPO_3S), "LiPo")
    panel = make_panel()
    assert panel.v_chem.currentData() is None                    # "from the macro"
    assert panel.virtual_battery() == "LiPo:2200:3"
    note = panel.bar.battery_note.full_text()
    assert note.startswith("LiPo 3S 2200 mAh") and "cells the macro's, capacity the macro's" in note
    editor.set("LiPo")                                            # declares neither: the values entered
    panel.set_start_params(capacity_mah=1500, series=2)
    assert panel.virtual_battery() == "LiPo:1500:2"
    assert "cells as entered for the run, capacity as entered for the run" in panel.bar.battery_note.full_text()


def test_the_flash_progress_bar_is_full_after_a_flash(qtbot, make_panel):
    panel = make_panel()
    connect(qtbot, panel)
    _flash(qtbot, panel)
    bar = panel.progress
    assert bar.maximum() > 0 and bar.value() == bar.maximum()
    assert "verified" in bar.toolTip()


def test_start_is_off_during_a_run_and_each_start_is_a_new_run_from_zero(qtbot, make_panel):
    panel = make_panel()
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    assert not panel.start_button.isEnabled() and "running" in panel.start_button.toolTip()
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as again:
        panel.start()
    assert again.args[0] is False and "Stop it first" in again.args[1]
    first = panel.plot.series
    qtbot.waitUntil(lambda: len(first) > 5, timeout=WAIT_MS)
    device = panel.connection.virtual_device
    panel.stop()
    qtbot.waitUntil(lambda: device.state != "running", timeout=WAIT_MS)
    qtbot.waitUntil(panel.start_button.isEnabled, timeout=WAIT_MS)
    first_end = first.last_x()
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    assert started.args[0], started.args[1]
    second = panel.plot.series
    assert second is not first and second is panel.series
    qtbot.waitUntil(lambda: len(second) > 2, timeout=WAIT_MS)
    assert second.buffer.column("t")[0] < first_end                # its axis starts again from 0
    choice = panel.live.run_choice
    assert choice.isVisibleTo(panel) and choice.count() == 2 and choice.currentIndex() == 1
    assert choice.itemText(0).startswith("Run 1: NiMh-dV")
    panel.live.runChosen.emit(0)
    assert panel.plot.series is first and len(first) > 5            # the earlier run, kept
    panel.live.runChosen.emit(1)
    assert panel.plot.series is second


def test_the_live_plot_has_the_cursor_readout(qtbot, make_panel):
    panel = make_panel()
    connect(qtbot, panel)
    flash_and_start(qtbot, panel)
    qtbot.waitUntil(lambda: len(panel.series) > 5, timeout=WAIT_MS)
    panel.plot.refresh()
    t = float(panel.series.buffer.column("t")[3])
    assert panel.live.readout.show_at(t)
    text = panel.live.readout.text()
    assert " V · " in text and " A" in text and "\nC1: " in text
