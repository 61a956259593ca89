"""One safety policy on every path (issue 25 point 1, issue 27): what ``safety.judge`` refuses never
reaches a charger from the window, whatever the path; the command line's --force-unsafe is the
only override and the slot lists mark what it put there, judged on the bytes read back. Warnings
are asked about once, Cancel the default. docs/safety.md states the policy."""
import os

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QMessageBox

from device_helpers import WAIT_MS, connect
from helpers import compiled
from zuml_studio.cli.main import main
from zuml_studio.data import standard_macros_dir
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.lang.eeprom import pack, slots
from zuml_studio.domain.start_templates import StartTemplate
from zuml_studio.ui.device import unsafe_dialog as dp

REAL_CONFIRM_WARNINGS = dp.confirm_warnings     # taken before tests/ui/conftest.py replaces it per test
pytestmark = pytest.mark.skipif(os.name != "posix", reason="the virtual chargers use ptys here")

# Unsafe only through the charger's start template: 13.5 V is 4.5 V per cell on the 3 cells of
# template 2 (factory: 3S LiPo), 3.4 V on 4. The compiler cannot know it (the bytes are made).
WALK = """MACRO Walk
  AKK_TYPE=LiPo
  START_SHABLON=2
  CHARGE_SECTION
    FAZE
    CONSTANT_I=1A
    IF(V>13.5V) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""


def cli(capsys, *args):
    capsys.readouterr()
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def refused_in_words(text: str) -> None:
    assert "the safety check refused it:" in text and "E303" in text, text
    assert "4.50 V per cell" in text and "[start template 2: " in text, text


def test_every_path_refuses_the_same_unsafe_macro(make_window, make_charger, qtbot, tmp_path, capsys,
                                                   warnings_asked):
    device, port = make_charger(battery="LiPo:2000:3", passport=None, speed=20000)
    source = tmp_path / "walk.zuml"
    source.write_text(WALK)
    record = compiled(WALK)
    (tmp_path / "walk.bin").write_bytes(record)
    (tmp_path / "image.bin").write_bytes(pack([compiled("LiPo"), record], 1024))
    w = make_window(str(source))
    panel = w.device_panel
    connect(qtbot, panel, port)

    # Upload (Ctrl+U) and Compile & Flash: refused with the reasons, no dialog to go ahead.
    for go in (w.upload, lambda: qtbot.mouseClick(panel.flash_button, Qt.MouseButton.LeftButton)):
        with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
            go()
        assert flashed.args[0] is False
        refused_in_words(flashed.args[1])
        assert panel.message_text() == flashed.args[1]
    # Restore of an image that holds it
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as restored:
        panel.restore(tmp_path / "image.bin")
    assert restored.args[:2] == ["restore", False]
    refused_in_words(restored.args[2])
    assert "slot 1 (Walk): E303" in restored.args[2]
    assert device.commits == 0 and warnings_asked == []
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS):
        panel.disconnect()

    # The command line: .zuml, .bin, image, restore, all refused without --force-unsafe.
    for args in (("flash", "--port", port, source), ("flash", "--port", port, tmp_path / "walk.bin"),
                 ("restore", "--port", port, tmp_path / "image.bin"),
                 ("image", "-o", tmp_path / "out.bin", tmp_path / "walk.bin")):
        code, out, err = cli(capsys, *args)
        assert code == 1 and "E303" in err and "--force-unsafe overrides" in err, (args, err)
    assert device.commits == 0 and not (tmp_path / "out.bin").exists()

    # The bench override: --force-unsafe prints every problem and a warning, and it is recorded.
    code, out, err = cli(capsys, "flash", "--force-unsafe", "--port", port, tmp_path / "walk.bin")
    assert code == 0 and "E303" in err and "zuml: warning:" in err and "--force-unsafe" in err
    code, out, err = cli(capsys, "slots", "--port", port)
    assert code == 0 and "UNSAFE (E303)" in out
    slots_line = next(line for line in out.splitlines() if "UNSAFE" in line)
    # A backup of the same bytes checked offline gets the same word (one verdict everywhere).
    (tmp_path / "backup.bin").write_bytes(device.eeprom)
    code, listed, err = cli(capsys, "image", "--list", tmp_path / "backup.bin")
    assert slots_line.split()[-2:] == next(line for line in listed.splitlines() if "UNSAFE" in line).split()[-2:]
    code, out, err = cli(capsys, "run", "--port", port, "--slot", 0, "--current", 1, "--no-sensor")
    assert code == 1 and "E303" in err and device.state == "idle"

    # The panel reads it back, marks it, and Start refuses it (no override in the window).
    connect(qtbot, panel, port)
    assert panel.slot_names() == ["Walk"]
    check = panel.table.item(0, 4)
    assert check.text() == "UNSAFE (E303)" and "4.50 V per cell" in check.toolTip()
    panel.set_start_params(current_a=1.0, series=3, sensor=False)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start(0)
    assert started.args[0] is False and started.args[1].startswith("Not started: Walk: the safety check refused it:")
    refused_in_words(started.args[1])
    assert device.state == "idle" and warnings_asked == []
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS):
        panel.disconnect()

    # Templates: the macro is judged with the template the charger holds. 4 cells make it safe;
    # storing 3 again is refused because the macro in slot 0 names it.
    code, out, err = cli(capsys, "templates", "set", "--port", port, 2, "--capacity", 2000, "--current", 1,
                         "--series", 4)
    assert code == 0, err
    assert "ok" in cli(capsys, "slots", "--port", port)[1].splitlines()[2]
    code, out, err = cli(capsys, "templates", "set", "--port", port, 2, "--series", 3)
    assert code == 1 and "slot 0 (Walk): E303" in err and "4.50 V per cell" in err
    with ChargerClient(port) as client:
        assert client.get_template(2).series == 4
        client.set_template(2, StartTemplate(capacity_mah=2000, current_a=1.0, series=3))   # another tool did it
    code, out, err = cli(capsys, "run", "--port", port, "--slot", 0, "--series", 4, "--current", 1, "--no-sensor")
    assert code == 1 and "[start template 2: " in err and "3 cells" in err, err
    connect(qtbot, panel, port)
    assert panel.table.item(0, 4).text() == "UNSAFE (E303)"
    panel.set_start_params(current_a=1.0, series=4, sensor=False)      # the values typed do not matter
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start(0)
    assert started.args[0] is False
    refused_in_words(started.args[1])
    assert device.state == "idle"


SAFE_WITH_WARNING = """MACRO Warm
  AKK_TYPE=LiIon
  SERIES=1
  CAPACITY=2000
  CHARGE_SECTION
    FAZE
    CONSTANT_I=1A
    IF(V>4.2S) STOP_FAZE
    IF(T>45) STOP_FAZE
    END_FAZE
    FAZE
    CONSTANT_V=4.23S
    IF(I<0.1A) STOP_FAZE
    IF(T>45) STOP_FAZE
    END_FAZE
  END_SECTION
END_MACRO
"""


def test_warnings_are_asked_once_and_cancel_writes_nothing(qtbot, make_panel, editor, monkeypatch, warnings_asked):
    from zuml_studio.safety import judge
    record = compiled(SAFE_WITH_WARNING)
    verdict = judge(record)
    assert verdict.safe and [w[:4] for w in verdict.warnings] == ["W303"]
    editor.value = (record, "Warm")
    panel = make_panel()
    panel.v_chem.setCurrentIndex(panel.v_chem.findData("LiIon"))
    panel.v_cells.setValue(1)
    connect(qtbot, panel)
    device = panel.connection.virtual_device
    monkeypatch.setattr(dp, "confirm_warnings", lambda parent, action, warnings: False)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    assert flashed.args == [False, "Not flashed: cancelled at the safety check's warnings."]
    assert device.commits == 0
    monkeypatch.undo()
    monkeypatch.setattr(dp, "confirm_warnings", lambda parent, action, warnings:
                        warnings_asked.append((action, warnings)) or True)
    for _attempt in range(2):
        with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
            panel.flash()
        assert flashed.args[0], flashed.args[1]
    panel.set_start_params(current_a=1.0, sensor=False)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    assert started.args[0], started.args[1]
    assert [action for action, _w in warnings_asked] == ["Flash"]       # once: not again, not at Start
    assert "W303" in warnings_asked[0][1][0]


def test_flashing_over_the_running_macro_says_the_run_keeps_its_copy(qtbot, make_panel, editor):
    editor.set("LiPo")
    panel = make_panel()
    panel.v_chem.setCurrentIndex(panel.v_chem.findData("LiPo"))
    connect(qtbot, panel)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS):
        panel.flash()
    panel.set_start_params(current_a=1.0, sensor=False)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    assert started.args[0], started.args[1]
    slower = (standard_macros_dir() / "LiPo.zuml").read_text().replace("CONSTANT_I=1C", "CONSTANT_I=0.9C", 1)
    editor.value = (compiled(slower), "LiPo")
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    ok, text = flashed.args
    assert ok and "The charge running now continues with the copy of LiPo it started with" in text, text


def test_the_question_names_each_warning_and_defaults_to_cancel(qtbot):
    box = dp.warnings_dialog(None, "Flash", ["W303 (byte 30): 4.23 V per cell, above LiIon's usual 4.20 V"])
    qtbot.addWidget(box)
    assert "1 warning" in box.text() and "• W303 (byte 30)" in box.informativeText()
    assert box.defaultButton() is not box.go_ahead and box.go_ahead.text() == "Flash"
    assert box.escapeButton() is box.defaultButton()


@pytest.mark.parametrize("click_go_ahead", [True, False])
def test_confirm_warnings_is_true_only_for_the_go_ahead_button(qtbot, monkeypatch, click_go_ahead):
    shown = []

    def exec_(box):
        shown.append(box)
        (box.go_ahead if click_go_ahead else box.button(QMessageBox.StandardButton.Cancel)).click()
        return 0
    monkeypatch.setattr(QMessageBox, "exec", exec_)
    assert REAL_CONFIRM_WARNINGS(None, "Start", ["W303: too high"]) is click_go_ahead
    assert shown and "W303" in shown[0].informativeText()

