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


def _b6_on_its_tx() -> bytes:
    """What a B6 with the ZUML firmware sends on its TX alone during a short run started on its buttons."""
    from zuml_studio.protocol import messages as m
    from zuml_studio.protocol.frames import encode_frame

    def tel(t, running, mah):
        return encode_frame(m.TELEMETRY, 0, m.Telemetry(
            time_s=t, task="charge", section="charge" if running else "", repetition=1 if running else 0, cycle=0,
            phase=1 if running else 0, run=1 if running else 0, running=running, paused=False, sensor=False,
            voltage_v=12.0 + t / 100, current_a=1.0 if running else 0.0, temp_c=None, heatsink_c=25.0,
            mah_in=mah, mah_out=0.0).encode())

    def event(number, t, kind, detail=""):
        return encode_frame(m.EVENT, 0, m.DeviceEvent(number, t, kind, "charge", 1 if "phase" in kind else 0, 1,
                                                      -1, detail).encode())

    lcd = encode_frame(m.LCD, 0, b"\x001 Bench" + b" " * 9)
    stream = lcd + tel(0, False, 0) + event(0, 0, "section") + event(1, 0, "phase_start")
    stream += b"".join(tel(t, True, t * 0.28) for t in range(1, 30))
    stream += event(2, 30, "phase_end", "IF(V>4.1S) STOP_FAZE") + event(3, 30, "finish", "end of macro")
    return stream + b"".join(tel(30 + t, False, 8.4) for t in range(1, 4))


def test_a_run_started_on_a_b6_heard_on_its_tx_is_recorded_in_its_pack(qtbot, panel, tmp_path):
    book = Logbook()
    pack = add_pack(book, "Bench LiPo", "LiPo", 3, 2000)
    live = LiveAttach(panel)
    asked = []
    live.ask = lambda parent, packs, where: asked.append(where) or packs[0]
    capture = tmp_path / "b6-tx.bin"
    capture.write_bytes(_b6_on_its_tx())
    with qtbot.waitSignal(live.recorded, timeout=WAIT_MS) as recorded:
        assert panel.replay(capture, speed=20)
    assert recorded.args[0].status == "added", recorded.args[0].message
    assert len(asked) == 1 and asked[0].startswith("port ")
    [session] = pack_sessions(book, pack)
    assert session.figures.charge_in_mah and session.figures.charge_in_mah > 0
    # the panel showed what the charger sent: its display, the phase with its end reason
    assert panel.front_panel.isVisible() and panel.front_panel.text() == ("1 Bench", "")
    qtbot.waitUntil(lambda: any(p.closed and p.reason == "IF(V>4.1S) STOP_FAZE" for p in panel.plot.phases()),
                    timeout=WAIT_MS)


def test_only_packs_that_match_the_run_are_offered(qtbot, panel):
    book = Logbook()
    add_pack(book, "LiPo 3S", "LiPo", 3, 2200)
    nimh = add_pack(book, "Bench NiMH", "NiMh", 4, 2000)
    live = LiveAttach(panel)
    assert live.run_battery() == (None, 0)                         # nothing connected: no run to know
    offered = []
    live.ask = lambda parent, packs, where: offered.append([p.name for p in packs]) or packs[0]
    connect(qtbot, panel)
    assert live.run_battery()[1] == 4                              # the run's 4 cells entered at START
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
