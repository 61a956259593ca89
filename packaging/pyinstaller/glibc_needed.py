"""Print the highest GLIBC symbol version any ELF file in a bundle needs: the oldest glibc (hence the
oldest distribution) the bundle runs on.  python glibc_needed.py BUNDLE_DIR

The version names sit as plain strings in each file's dynamic string table, so a byte search finds
them without binutils; the bundle holds no glibc of its own, so every name found is one it needs."""
from __future__ import annotations

import re
import sys
from pathlib import Path

VERSION = re.compile(rb"GLIBC_(\d+)\.(\d+)(?:\.(\d+))?\x00")


def needed(bundle: Path) -> tuple[tuple[int, ...], Path] | None:
    """(highest version, a file needing it), or None when no file names one."""
    best: tuple[tuple[int, ...], Path] | None = None
    for path in sorted(p for p in bundle.rglob("*") if p.is_file() and not p.is_symlink()):
        with path.open("rb") as fh:
            if fh.read(4) != b"\x7fELF":
                continue
            body = fh.read()
        for m in VERSION.finditer(body):
            version = tuple(int(g) for g in m.groups() if g is not None)
            if best is None or version > best[0]:
                best = (version, path.relative_to(bundle))
    return best


def main(argv: list[str]) -> int:
    if len(argv) != 1 or not Path(argv[0]).is_dir():
        print("usage: python glibc_needed.py BUNDLE_DIR", file=sys.stderr)
        return 2
    found = needed(Path(argv[0]))
    if found is None:
        print("the bundle names no GLIBC symbol version")
        return 1
    version, path = found
    print(f"highest GLIBC symbol version needed: GLIBC_{'.'.join(map(str, version))} (by {path}); "
          "the bundle runs on that glibc or newer")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
