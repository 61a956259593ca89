"""Where the tests' copies of real recordings are (tests/data/logs, sources in tests/data/README.md)."""
from pathlib import Path

DATA = Path(__file__).resolve().parents[1] / "data" / "logs"


def data(name: str) -> bytes:
    return (DATA / name).read_bytes()


def path(name: str) -> Path:
    return DATA / name
