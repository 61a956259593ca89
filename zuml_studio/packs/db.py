"""The logbook's SQLite database: opened in WAL mode (readers never block the one writer, and a crash
mid-write leaves the last committed state), its schema brought up to date by numbered migrations, and
a damaged or foreign file reported, never replaced: it holds the user's history, which nothing can
rebuild. Every write is one ``BEGIN IMMEDIATE`` transaction, so two instances of the app take turns
(the other waits up to ``BUSY_MS``) instead of interleaving."""
from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ..user_dirs import data_dir
from ..errors import ZumlError
from ..i18n import _

FILE_NAME = "packs.sqlite3"
# PRAGMA application_id: 'ZUPK', so a SQLite file of another program is told apart from ours.
APPLICATION_ID = 0x5A55504B
BUSY_MS = 10000

# Migration n (1-based) takes the schema from version n-1 to n; never edit one that has shipped, add one.
MIGRATIONS: tuple[str, ...] = (
    """
    CREATE TABLE packs (
        id INTEGER PRIMARY KEY,
        name TEXT NOT NULL UNIQUE COLLATE NOCASE,
        chemistry TEXT NOT NULL,
        cells INTEGER NOT NULL,
        capacity_mah REAL NOT NULL,
        bought TEXT,
        notes TEXT NOT NULL DEFAULT '',
        serial TEXT,
        created TEXT NOT NULL
    );
    CREATE TABLE sessions (
        id INTEGER PRIMARY KEY,
        pack_id INTEGER NOT NULL REFERENCES packs(id) ON DELETE CASCADE,
        sha256 TEXT NOT NULL UNIQUE,
        file TEXT NOT NULL,
        source TEXT NOT NULL,
        format TEXT,
        device TEXT,
        recorded TEXT NOT NULL,
        recorded_from TEXT NOT NULL,
        imported TEXT NOT NULL,
        duration_s REAL,
        charge_in_mah REAL,
        charge_out_mah REAL,
        energy_in_wh REAL,
        energy_out_wh REAL,
        capacity_mah REAL,
        capacity_from TEXT,
        resistance_mohm_per_cell REAL,
        resistance_from TEXT,
        cell_deviation_mv REAL,
        t_max_c REAL
    );
    CREATE INDEX sessions_pack ON sessions(pack_id, recorded);
    """,
    """
    ALTER TABLE sessions ADD COLUMN passport_errors INTEGER;
    ALTER TABLE sessions ADD COLUMN passport_critical INTEGER;
    CREATE TABLE attachments (
        key TEXT PRIMARY KEY,
        pack_id INTEGER REFERENCES packs(id) ON DELETE CASCADE
    );
    """,
    """
    ALTER TABLE sessions ADD COLUMN foreign_reason TEXT;
    ALTER TABLE sessions ADD COLUMN same_files TEXT NOT NULL DEFAULT '';
    """,
)
SCHEMA_VERSION = len(MIGRATIONS)


class LogbookError(ZumlError):
    """The logbook cannot be opened or written; the message names the file and what to do."""


def default_path() -> Path:
    return data_dir() / FILE_NAME


class Logbook:
    """One connection to the database; ``write()`` is its only way to change it."""

    def __init__(self, path: Path | str | None = None, *, migrate_to: int = SCHEMA_VERSION):
        self.path = Path(path) if path is not None else default_path()
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise LogbookError(_("{path}: cannot create the folder: {error}").format(
                    path=self.path.parent, error=exc.strerror or exc)) from None
        existed = self.path.exists() and self.path.stat().st_size > 0
        try:
            self.conn = sqlite3.connect(self.path, timeout=BUSY_MS / 1000, isolation_level=None,
                                        check_same_thread=False)
        except sqlite3.Error as exc:
            raise LogbookError(_("{path}: cannot open the pack logbook: {error}").format(
                    path=self.path, error=exc)) from None
        try:
            self._check(existed)
            self.conn.execute("PRAGMA journal_mode=WAL")
            self.conn.execute("PRAGMA foreign_keys=ON")
            self._migrate(migrate_to)
        except sqlite3.OperationalError as exc:    # locked, read-only, no space: the file may be sound
            self.conn.close()
            raise self._unwritable(exc) from None
        except sqlite3.DatabaseError as exc:       # not a database, malformed
            self.conn.close()
            raise self._damaged(str(exc)) from None
        except LogbookError:
            self.conn.close()
            raise

    def _damaged(self, reason: str) -> LogbookError:
        return LogbookError(_("{path}: the pack logbook is damaged ({reason}); it is left as it is: restore it "
                              "from a backup, or move it away to start a new one").format(path=self.path,
                                                                                          reason=reason))

    def _unwritable(self, exc: sqlite3.OperationalError) -> LogbookError:
        if "locked" in str(exc) or "busy" in str(exc):
            return LogbookError(_("{path}: the pack logbook is busy (another ZUML Studio is writing it): "
                                  "{error}").format(path=self.path, error=exc))
        return LogbookError(_("{path}: cannot write the pack logbook: {error}; this change is not kept, what "
                              "was written before it is").format(path=self.path, error=exc))

    def _check(self, existed: bool) -> None:
        if not existed:
            return
        app = self.conn.execute("PRAGMA application_id").fetchone()[0]
        if app != APPLICATION_ID:
            raise LogbookError(_("{path}: a SQLite file, but not a ZUML Studio pack logbook; it is left as it "
                                 "is").format(path=self.path))
        result = self.conn.execute("PRAGMA quick_check").fetchone()[0]
        if result != "ok":
            raise self._damaged(result)

    def _migrate(self, target: int) -> None:
        self._refuse_newer(self.version)
        if self.version >= target:
            return                        # up to date: opening to read takes no lock
        with self.write():
            version = self.version        # again, under the lock: another instance may have migrated it
            if version == 0:
                self.conn.execute(f"PRAGMA application_id={APPLICATION_ID}")
            for n in range(version + 1, target + 1):
                for statement in _statements(MIGRATIONS[n - 1]):
                    self.conn.execute(statement)
                self.conn.execute(f"PRAGMA user_version={n}")

    def _refuse_newer(self, version: int) -> None:
        if version > SCHEMA_VERSION:
            raise LogbookError(_("{path}: written by a newer ZUML Studio (schema {found}, this one knows "
                                 "{known}); it is left as it is").format(
                    path=self.path, found=version, known=SCHEMA_VERSION))

    @property
    def version(self) -> int:
        return self.conn.execute("PRAGMA user_version").fetchone()[0]

    @contextmanager
    def write(self) -> Iterator[sqlite3.Connection]:
        """One transaction, taken before it reads (BEGIN IMMEDIATE): another writer waits its turn. A write
        that fails (a full disk at COMMIT, a read-only folder holding the ``-wal`` file) is rolled back and
        raised as one ``LogbookError`` line: what was written before this transaction is kept, nothing of it."""
        try:
            self.conn.execute("BEGIN IMMEDIATE")
        except sqlite3.OperationalError as exc:
            raise self._unwritable(exc) from None
        try:
            yield self.conn
            self.conn.execute("COMMIT")
        except sqlite3.OperationalError as exc:
            self._rollback()
            raise self._unwritable(exc) from None
        except BaseException:
            self._rollback()
            raise

    def _rollback(self) -> None:
        if self.conn.in_transaction:
            try:
                self.conn.execute("ROLLBACK")
            except sqlite3.Error:
                pass                # the transaction is gone already (SQLite rolls back on some errors)

    def read(self, sql: str, params: tuple = ()) -> list[sqlite3.Row]:
        cur = self.conn.execute(sql, params)
        cur.row_factory = sqlite3.Row
        return cur.fetchall()

    def close(self) -> None:
        self.conn.close()


def _statements(script: str) -> list[str]:
    """A migration's statements, run one by one inside the migration's transaction (executescript
    would commit it first)."""
    return [s.strip() for s in script.split(";") if s.strip()]
