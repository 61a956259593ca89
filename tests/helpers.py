"""Shared test helpers: paths of the project's files."""
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MACROS = ROOT / "macros"
SEED_MACROS = ("Pb", "NiCd", "NiMh", "LiPo", "LiIon", "LiFe")


def seed_text(name: str) -> str:
    return (MACROS / f"{name}.zuml").read_text()
