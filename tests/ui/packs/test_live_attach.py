"""Live runs on the built-in virtual charger recorded into a pack: asked once, remembered, recorded."""
import pytest

from device_helpers import WAIT_MS, Editor, connect, flash_and_start
from zuml_studio.packs.db import Logbook
from zuml_studio.packs.register import add_pack, attachment
from zuml_studio.packs.sessions import pack_sessions
from zuml_studio.ui.packs.live_attach import CANCELLED, LiveAttach


@pytest.fixture
def panel(qtbot, tmp_path, monkeypatch):
    monkeypatch.setenv("ZUML_STUDIO_DATA_DIR", str(tmp_path / "data"))
    from zuml_studio.ui.device import DevicePanel

    made = DevicePanel(Editor(), tmp_path / "sessions", port_lister=lambda: [])
    qtbot.addWidget(made)
    made.resize(1400, 380)
    made.show()
    yield made
    made.shutdown()


def _run(qtbot, panel, live):
    """START, some telemetry, STOP; returns the recorded ImportResult."""
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    assert started.args[0], started.args[1]
    qtbot.waitUntil(lambda: len(live.collector._samples) > 5, timeout=WAIT_MS)
    with qtbot.waitSignal(live.recorded, timeout=WAIT_MS) as recorded:
        panel.stop()
    return recorded.args[0]


def test_a_run_is_asked_for_once_and_recorded_in_its_pack(qtbot, panel):
    book = Logbook()
    pack = add_pack(book, "Bench NiMH", "NiMh", 4, 2000)
    live = LiveAttach(panel)
    asked = []
    live.ask = lambda parent, packs, where: asked.append(where) or packs[0]
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    assert len(asked) == 1
    qtbot.waitUntil(lambda: len(live.collector._samples) > 5, timeout=WAIT_MS)
    with qtbot.waitSignal(live.recorded, timeout=WAIT_MS) as recorded:
        panel.stop()
    assert recorded.args[0].status == "added", recorded.args[0].message
    second = _run(qtbot, panel, live)
    assert second.status == "added" and len(asked) == 1           # remembered: not asked again
    sessions = pack_sessions(book, pack)
    assert [s.source for s in sessions] == ["live", "live"]
    assert all(s.figures.charge_in_mah and s.figures.charge_in_mah > 0 for s in sessions)
    assert attachment(book, live._where()[0]) == (True, pack)


def test_no_pack_is_remembered_and_a_closed_question_asks_again(qtbot, panel):
    book = Logbook()
    add_pack(book, "Bench NiMH", "NiMh", 4, 2000)
    live = LiveAttach(panel)
    answers = [CANCELLED, None]
    live.ask = lambda parent, packs, where: answers.pop(0)
    connect(qtbot, panel)
    ok, _text = flash_and_start(qtbot, panel)
    assert ok and answers == [None] and not live.collector.collecting
    assert attachment(book, live._where()[0]) == (False, None)
    panel.stop()
    qtbot.waitUntil(panel.start_button.isEnabled, timeout=WAIT_MS)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS):
        panel.start()
    assert answers == [] and not live.collector.collecting
    assert attachment(book, live._where()[0]) == (True, None)       # "no pack here", remembered
    from zuml_studio.ui.packs.packs_panel import PacksPanel

    packs = PacksPanel(book)
    qtbot.addWidget(packs)
    with qtbot.waitSignal(packs.statusMessage) as said:
        packs.ask_again_button.click()
    assert "1 charger will be asked again" in said.args[0]
    assert attachment(book, live._where()[0]) == (False, None)



def test_only_packs_that_match_the_run_are_offered(qtbot, panel):
    book = Logbook()
    add_pack(book, "LiPo 3S", "LiPo", 3, 2200)
    nimh = add_pack(book, "Bench NiMH", "NiMh", 4, 2000)
    live = LiveAttach(panel)
    assert live.run_battery()[1] == 4                              # the run's 4 cells entered at START
    offered = []
    live.ask = lambda parent, packs, where: offered.append([p.name for p in packs]) or packs[0]
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    assert offered == [["Bench NiMH"]] and live._pack == nimh      # a 3S LiPo is no choice for a 4-cell run
    panel.stop()


def test_with_no_pack_matching_the_run_nothing_is_recorded_nor_remembered(qtbot, panel):
    book = Logbook()
    add_pack(book, "LiPo 3S", "LiPo", 3, 2200)
    live = LiveAttach(panel)
    asked = []
    live.ask = lambda parent, packs, where: asked.append(packs) or packs[0]
    said = []
    live.statusMessage.connect(said.append)
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    assert asked == [] and live._pack is None and not live.collector.collecting
    assert any(m.startswith("No pack in the logbook matches this run") for m in said)
    assert attachment(book, live._where()[0]) == (False, None)
    panel.stop()
