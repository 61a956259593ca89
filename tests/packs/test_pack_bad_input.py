"""The logbook under bad input (issue 33 §3; shared/repro/hostile-3: import_nonutf8_name.sh, names.py,
live_same_second.py, ro_wal_traceback.sh): names that are not UTF-8 stored and shown escaped, the
import going on; control characters escaped on the terminal; a write error one line saying what was
kept; a live run never written over another."""
import os
import sqlite3

import pytest

from zuml_studio.cli.main import main
from zuml_studio.logs import read_log_file
from zuml_studio.packs.db import Logbook, LogbookError
from zuml_studio.packs.live import record_run
from zuml_studio.packs.register import add_pack, get_pack
from zuml_studio.packs.sessions import pack_sessions
from zuml_studio.packs.text import path_of, printable, storable

DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data" / "logs"


def _csv(offset: float) -> bytes:
    """A charge; each offset its own length (charges of the same length and mAh are one charge twice)."""
    return ("Zeit [s];Spannung [V];Strom [A]\n" + "".join(
        f"{i * 10};{7.4 + i * 0.003 + offset:.4f};2,0\n".replace(".", ",")
        for i in range(100 + int(offset * 100)))).encode()


@pytest.fixture(autouse=True)
def data_dir(tmp_path, monkeypatch):
    monkeypatch.setenv("ZUML_STUDIO_DATA_DIR", str(tmp_path / "data"))


def test_a_file_name_that_is_not_utf8_is_stored_escaped_and_the_import_goes_on(tmp_path, capsys):
    folder = tmp_path / "logs"
    folder.mkdir()
    latin1 = os.fsdecode(b"b_Ladung_M\xfcller.csv")                  # an old archive's Latin-1 "Müller"
    for k, name in enumerate(["a_first.csv", latin1, "c_last.csv"]):
        (folder / name).write_bytes(_csv(k / 10))
    assert main(["pack", "add", "P", "--chemistry", "LiPo", "--cells", "2", "--capacity", "2000"]) == 0
    assert main(["pack", "import", str(folder), "--pack", "P"]) == 0
    out = capsys.readouterr().out
    assert "added: " + str(folder / "b_Ladung_M\\xfcller.csv") + "\n" in out
    assert "pack 'P': 3 added, 0 already known, 0 not read" in out
    book = Logbook()
    files = [s.file for s in pack_sessions(book, get_pack(book, "P"))]
    assert str(folder / "b_Ladung_M\\xfcller.csv") in files
    assert path_of(str(folder / "b_Ladung_M\\xfcller.csv")) == folder / latin1     # opened again by its bytes
    assert main(["pack", "show", "P"]) == 0
    assert "b_Ladung_M\\xfcller.csv" in capsys.readouterr().out


def test_a_pack_name_from_argv_that_is_not_utf8_is_kept_escaped(capsys):
    name = os.fsdecode(b"Akku\xfc")
    assert main(["pack", "add", name, "--chemistry", "LiPo", "--cells", "2", "--capacity", "2000",
                 "--notes", os.fsdecode(b"n\xe4")]) == 0
    book = Logbook()
    pack = get_pack(book, name)                       # the same argument finds it
    assert (pack.name, pack.notes) == ("Akku\\xfc", "n\\xe4")


def test_control_characters_in_names_and_notes_are_escaped_on_the_terminal(capsys):
    assert main(["pack", "add", "\x1b[2J\x1b[31mRED", "--chemistry", "LiPo", "--cells", "2", "--capacity", "2000",
                 "--notes", "a\x07b\u202ec"]) == 0
    capsys.readouterr()
    assert main(["pack", "list"]) == 0
    assert main(["pack", "show", "\x1b[2J\x1b[31mRED"]) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\x07" not in out and "\u202e" not in out
    assert "\\x1b[2J\\x1b[31mRED: LiPo 2S 2000 mAh" in out and "notes: a\\x07b\\u202ec" in out


def test_printable_keeps_readable_text_and_escapes_the_rest():
    assert printable("Пакет 🔋 ñ Ω") == "Пакет 🔋 ñ Ω"
    assert printable("a\tb\rc\x7fd\u200be") == "a\\x09b\\x0dc\\x7fd\\u200be"
    assert storable(os.fsdecode(b"x\xff")) == "x\\xff"


class _FullDisk:
    """A connection whose COMMIT fails as on a full disk; everything else goes to the real one."""

    def __init__(self, conn):
        self.conn = conn

    def execute(self, sql, *args):
        if sql == "COMMIT":
            raise sqlite3.OperationalError("database or disk is full")
        return self.conn.execute(sql, *args)

    def __getattr__(self, name):
        return getattr(self.conn, name)


def test_a_write_that_fails_at_commit_is_one_line_and_keeps_what_was_written_before(tmp_path):
    book = Logbook(tmp_path / "p.sqlite3")
    add_pack(book, "kept", "LiPo", 2, 2000)
    real = book.conn
    book.conn = _FullDisk(real)
    with pytest.raises(LogbookError) as caught:
        add_pack(book, "lost", "LiPo", 2, 2000)
    book.conn = real
    message = str(caught.value)
    assert "\n" not in message and message.endswith(
        "cannot write the pack logbook: database or disk is full; this change is not kept, what was written "
        "before it is")
    assert [r[0] for r in book.read("SELECT name FROM packs")] == ["kept"]
    assert not real.in_transaction


def test_an_import_stopped_by_a_write_error_says_how_many_files_were_kept(tmp_path, capsys, monkeypatch):
    folder = tmp_path / "logs"
    folder.mkdir()
    for k in range(3):
        (folder / f"{k}.csv").write_bytes(_csv(k / 10))
    assert main(["pack", "add", "P", "--chemistry", "LiPo", "--cells", "2", "--capacity", "2000"]) == 0
    import zuml_studio.packs.sessions as sessions
    real = sessions.import_file
    calls = []

    def failing(book, pack, path, **kw):
        calls.append(path)
        if len(calls) == 3:
            raise LogbookError("x: cannot write the pack logbook: disk I/O error")
        return real(book, pack, path, **kw)
    monkeypatch.setattr(sessions, "import_file", failing)
    assert main(["pack", "import", str(folder), "--pack", "P"]) == 1
    err = capsys.readouterr().err
    assert err.strip().endswith("(the import stopped there; the 2 files added before it are kept)")
    assert "Traceback" not in err


def test_two_live_runs_in_one_second_and_names_made_equal_never_overwrite(tmp_path):
    samples = list(read_log_file(DATA / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt").samples[:50])
    book = Logbook(tmp_path / "p.sqlite3")
    packs = [add_pack(book, "a/b", "LiPo", 4, 1500), add_pack(book, "a?b", "LiPo", 4, 1500)]
    results = [record_run(book, pack, samples[:20 + 10 * k], "x", folder=tmp_path / "runs")
               for k, pack in enumerate(packs + packs)]
    assert [r.status for r in results] == ["added"] * 4
    assert len({r.path for r in results}) == 4
    for k, r in enumerate(results):                  # each file still holds its own run
        assert len(read_log_file(r.path).samples) == 20 + 10 * k
