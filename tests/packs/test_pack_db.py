"""The logbook's database: WAL, migrations, damaged and foreign files reported and left alone, and two
writers at once."""
import sqlite3
import threading

import pytest

from zuml_studio.packs import db
from zuml_studio.packs.db import Logbook, LogbookError
from zuml_studio.packs.register import add_pack, get_pack, list_packs


def test_new_logbook_is_wal_at_the_current_schema(tmp_path):
    book = Logbook(tmp_path / "p.sqlite3")
    assert book.conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    assert book.version == db.SCHEMA_VERSION
    assert book.conn.execute("PRAGMA application_id").fetchone()[0] == db.APPLICATION_ID


def test_default_path_is_in_the_data_dir(tmp_path, monkeypatch):
    monkeypatch.setenv("ZUML_STUDIO_DATA_DIR", str(tmp_path / "data"))
    assert Logbook().path == tmp_path / "data" / "packs.sqlite3"


def test_a_version_1_logbook_is_migrated_and_keeps_its_packs(tmp_path):
    path = tmp_path / "p.sqlite3"
    old = Logbook(path, migrate_to=1)
    assert old.version == 1
    old.conn.execute("INSERT INTO packs (name, chemistry, cells, capacity_mah, created) "
                     "VALUES ('Old', 'NiMh', 4, 2000, '2020-01-01')")
    old.close()
    book = Logbook(path)
    assert book.version == db.SCHEMA_VERSION == 3
    assert get_pack(book, "Old").cells == 4
    columns = {r[1] for r in book.conn.execute("PRAGMA table_info(sessions)")}
    assert {"passport_critical", "passport_errors", "foreign_reason"} <= columns


def test_a_newer_schema_is_refused(tmp_path):
    path = tmp_path / "p.sqlite3"
    Logbook(path).conn.execute(f"PRAGMA user_version={db.SCHEMA_VERSION + 1}")
    with pytest.raises(LogbookError, match="newer ZUML Studio"):
        Logbook(path)


def test_a_damaged_file_is_reported_and_left_as_it_is(tmp_path):
    path = tmp_path / "p.sqlite3"
    book = Logbook(path)
    add_pack(book, "A", "LiPo", 3, 2200)
    book.conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    book.close()
    data = bytearray(path.read_bytes())
    data[100:4096] = b"\xff" * (4096 - 100)         # the schema page torn
    path.write_bytes(bytes(data))
    with pytest.raises(LogbookError, match="damaged") as caught:
        Logbook(path)
    assert "\n" not in str(caught.value) and str(path) in str(caught.value)
    assert path.read_bytes() == bytes(data)


def test_a_file_that_is_not_sqlite_is_reported_and_left_as_it_is(tmp_path):
    path = tmp_path / "p.sqlite3"
    path.write_bytes(b"my notes, not a database\n" * 100)
    with pytest.raises(LogbookError, match="damaged"):
        Logbook(path)
    assert path.read_bytes() == b"my notes, not a database\n" * 100


def test_another_programs_sqlite_file_is_refused(tmp_path):
    path = tmp_path / "p.sqlite3"
    other = sqlite3.connect(path)
    other.execute("CREATE TABLE t (x)")
    other.commit()
    other.close()
    with pytest.raises(LogbookError, match="not a ZUML Studio pack logbook"):
        Logbook(path)


def test_two_instances_writing_at_once_lose_nothing(tmp_path):
    path = tmp_path / "p.sqlite3"
    Logbook(path).close()
    errors = []

    def writer(prefix: str) -> None:
        book = Logbook(path)             # its own connection, as another instance of the app has
        try:
            for n in range(25):
                add_pack(book, f"{prefix}{n}", "NiMh", 4, 2000)
        except Exception as exc:          # noqa: BLE001 - the test reports whatever a writer met
            errors.append(exc)
        finally:
            book.close()

    threads = [threading.Thread(target=writer, args=(p,)) for p in "AB"]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    book = Logbook(path)
    assert len(list_packs(book)) == 50
    assert book.conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"


def test_a_logbook_held_by_another_writer_is_busy_not_damaged(tmp_path, monkeypatch):
    path = tmp_path / "p.sqlite3"
    Logbook(path).close()
    monkeypatch.setattr(db, "BUSY_MS", 50)
    holder = sqlite3.connect(path, isolation_level=None)
    holder.execute("BEGIN EXCLUSIVE")                # another instance in the middle of a write
    try:
        book = Logbook(path)                         # reading needs no lock
        with pytest.raises(LogbookError, match="busy"):
            add_pack(book, "A", "LiPo", 3, 2200)
        assert list_packs(book) == []
    finally:
        holder.execute("ROLLBACK")
        holder.close()
    assert add_pack(Logbook(path), "A", "LiPo", 3, 2200).name == "A"


def test_a_read_only_logbook_is_not_called_damaged(tmp_path):
    import os
    path = tmp_path / "p.sqlite3"
    Logbook(path).close()
    os.chmod(path, 0o444)
    try:
        if os.access(path, os.W_OK):
            pytest.skip("running as root: a read-only mode does not stop writes")
        with pytest.raises(LogbookError) as caught:
            add_pack(Logbook(path), "A", "LiPo", 3, 2200)
        assert "damaged" not in str(caught.value)
    finally:
        os.chmod(path, 0o644)
