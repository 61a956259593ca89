"""Sessions: import by hash, folders, dates, trend points and the health verdict."""
import shutil

import pytest

from zuml_studio.packs.db import Logbook
from zuml_studio.packs.figures import SessionFigures
from zuml_studio.packs.health import health, trend
from zuml_studio.packs.register import (PackError, add_pack, attach, attachment, attachment_key,
                                        forget_attachments, remove_pack)
from zuml_studio.packs.sessions import Session, import_files, pack_sessions
from zuml_studio.packs.summary import CSV_COLUMNS, pack_summary, write_sessions_csv

DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data" / "logs"
NIMH = ["eStationBC6_2008-07-05_EmpfaengerAA.osd", "UltramatACDCEQ_2014-09-16_4S_NiMH_cycle.osd"]


@pytest.fixture
def book(tmp_path):
    return Logbook(tmp_path / "p.sqlite3")


def test_same_bytes_twice_are_one_session(book, tmp_path):
    pack = add_pack(book, "NiMH 4S", "NiMH", 4, 1200)
    copy = tmp_path / "renamed.osd"
    shutil.copy(DATA / NIMH[0], copy)
    results = import_files(book, pack, [DATA / NIMH[0], copy])
    assert [r.status for r in results] == ["added", "known"]
    assert "NiMH 4S" in results[1].message
    other = add_pack(book, "Other", "NiMH", 4, 1200)
    assert import_files(book, other, [copy])[0].status == "known"          # not counted in a second pack
    assert len(pack_sessions(book, pack)) == 1 and pack_sessions(book, other) == []


def test_a_folder_is_imported_whole_and_unreadable_files_are_reported(book, tmp_path):
    folder = tmp_path / "logs"
    (folder / "sub").mkdir(parents=True)
    shutil.copy(DATA / NIMH[0], folder / NIMH[0])
    shutil.copy(DATA / NIMH[1], folder / "sub" / NIMH[1])
    (folder / "notes.txt").write_text("not a log")
    (folder / ".hidden").write_text("skipped")
    pack = add_pack(book, "NiMH 4S", "NiMH", 4, 1200)
    seen = []
    results = import_files(book, pack, [folder], lambda done, total, r: seen.append((done, total)))
    assert sorted(r.status for r in results) == ["added", "added", "error"]
    assert seen == [(1, 3), (2, 3), (3, 3)]
    sessions = pack_sessions(book, pack)
    # The Ultramat .osd holds its own start time stamp; the eStation's (an older DataExplorer) none.
    assert [(s.recorded, s.recorded_from) for s in sessions] == [("2008-07-05", "file name"),
                                                                 ("2014-09-15T20:16:25+00:00", "log")]


def test_trend_points_and_csv(book, tmp_path):
    pack = add_pack(book, "NiMH 4S", "NiMH", 4, 1200)
    import_files(book, pack, [DATA / n for n in NIMH])
    info = pack_summary(book, pack)
    sessions = info["sessions"]
    assert [p["capacity_pct"] for p in info["trend"]] == [
            pytest.approx(s["capacity_mah"] / 1200 * 100, abs=0.05) for s in sessions]
    assert [p["resistance_mohm_per_cell"] for p in info["trend"]] == [s["resistance_mohm_per_cell"] for s in sessions]
    out = tmp_path / "s.csv"
    assert write_sessions_csv(book, pack, out) == 2
    lines = out.read_text(encoding="utf-8").splitlines()
    assert lines[0].split(",") == list(CSV_COLUMNS) and len(lines) == 3


def _session(date, cap=None, r=None, dev=None):
    f = SessionFigures(3600, None, None, None, None, cap, "discharge" if cap else None, r, "rest steps" if r else None,
                       dev, None)
    return Session(0, f"{date}.lov", "file", None, None, date, "file name", f)


@pytest.mark.parametrize("sessions, verdict, words", [
    ([], "unknown", "no session"),
    ([_session("2024-01-01", cap=1900, r=20, dev=10)], "good", "capacity 95 %"),
    ([_session("2024-01-01", cap=1900), _session("2025-01-01", cap=1590)], "poor", "below 80 %"),
    ([_session("2024-01-01", r=20), _session("2025-01-01", r=30)], "poor", "1.50× its first value"),
    ([_session("2024-01-01", r=20), _session("2025-01-01", r=29)], "good", "1.45×"),
    ([_session("2024-01-01", dev=31)], "poor", "a cell is drifting"),
    ([_session("2024-01-01", dev=30)], "good", "30 mV apart"),
])
def test_health_verdicts(sessions, verdict, words):
    pack = add_pack.__globals__["Pack"](1, "P", "LiPo", 4, 2000)
    h = health(pack, sessions)
    assert h.verdict == verdict and any(words in r for r in h.reasons), h.reasons
    assert len(trend(pack, sessions)) == len(sessions)


def test_register_errors_and_attachments(book):
    pack = add_pack(book, "Turnigy 4S #2", "LiPo", 4, 2200, serial="A1")
    for bad in (dict(name=" x"), dict(chemistry="Unobtainium"), dict(cells=0), dict(capacity_mah=-1),
                dict(bought="last May")):
        kw = dict(name="New", chemistry="LiPo", cells=4, capacity_mah=2200) | bad
        name = kw.pop("name")
        with pytest.raises(PackError):
            add_pack(book, name, kw.pop("chemistry"), kw.pop("cells"), kw.pop("capacity_mah"), **kw)
    with pytest.raises(PackError, match="exists already"):
        add_pack(book, "turnigy 4s #2", "LiPo", 4, 2200)
    key = attachment_key("/dev/ttyUSB0", "A1")
    assert key == "serial:A1" and attachment_key("/dev/ttyUSB0", None) == "port:/dev/ttyUSB0"
    assert attachment(book, key) == (False, None)
    attach(book, key, pack)
    assert attachment(book, key) == (True, pack)
    attach(book, "port:/dev/ttyACM0", None)                  # "no pack here", remembered
    assert attachment(book, "port:/dev/ttyACM0") == (True, None)
    assert forget_attachments(book, "port:/dev/ttyACM0") == 1
    assert attachment(book, "port:/dev/ttyACM0") == (False, None)
    attach(book, "port:/dev/ttyACM0", None)
    assert forget_attachments(book) == 2 and attachment(book, key) == (False, None)
    attach(book, key, pack)
    remove_pack(book, pack.name)
    assert attachment(book, key) == (False, None)           # its pack gone: asked again
