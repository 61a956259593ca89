"""Flashing through a faulty line: is the result the truth, and does it get through?

Run: python benchmarks/bench_flash_faults.py [FLASHES] [BAUD]

1. BER 1e-3 (both directions) at 115200 baud, paced: FLASHES (default 200) flashes as
   `zuml flash` does them (connect, read the present image, merge a macro, write, verify),
   each on a fresh virtual charger with its own seed. Target: >= 99 % succeed.
2. A link that dies after N received bytes, N spread over a whole flash: every outcome must
   be said truthfully: an error that says "nothing written" must leave the previous image,
   "the new image" must hold it, and "either" must hold one of the two (never a mix).

Prints the success rate, the failures by kind, and the truth table of the disconnects.
"""
from __future__ import annotations

import collections
import sys
import time

from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.errors import CommitUncertain, DeviceLinkError
from zuml_studio.device.zuml.flashing import merge_record
from zuml_studio.virtual.transport import serve_pty
from zuml_studio.virtual.virtual_charger import Faults, VirtualCharger
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.eeprom import pack

MACROS = ("NiMh", "LiPo", "NiCd", "LiIon", "Pb", "LiFe")


def record(name: str) -> bytes:
    from pathlib import Path
    text = (Path(__file__).resolve().parent.parent / "macros" / f"{name}.zuml").read_text()
    return compile_source(text).record


def flash_once(seed: int, baud: int, faults: Faults, before: bytes, rec: bytes):
    """-> (outcome, error or None, eeprom before, eeprom after, the image meant)."""
    device = VirtualCharger(speed=1, faults=faults, seed=seed)
    device.eeprom[:len(before)] = before
    port, stop = serve_pty(device, baud=baud)
    wanted = None
    try:
        try:
            with ChargerClient(port, baud) as client:
                current = client.read_image()
                merged = merge_record(current, rec, None)
                wanted = merged.image + b"\xff" * (len(current) - len(merged.image))
                client.write_image(merged.image, current=current)
            return "ok", None, wanted, bytes(device.eeprom)
        except DeviceLinkError as exc:
            return type(exc).__name__, exc, wanted, bytes(device.eeprom)
    finally:
        stop()
        device.close()


def ber_run(flashes: int, baud: int) -> None:
    before = pack([record("NiMh"), record("LiPo")], 1024)
    kinds = collections.Counter()
    t0 = time.monotonic()
    for i in range(flashes):
        outcome, exc, wanted, after = flash_once(i, baud, Faults(ber=1e-3), before, record(MACROS[2 + i % 4]))
        kinds[outcome] += 1
        if outcome == "ok" and after != wanted:
            kinds["ok but the EEPROM differs (a lie)"] += 1
        if outcome != "ok" and after not in (before, wanted):
            kinds["a mixed image"] += 1
    ok = kinds["ok"]
    print(f"BER 1e-3, {baud} baud: {ok}/{flashes} flashes succeeded ({100 * ok / flashes:.1f} %, target >= 99 %) "
          f"in {time.monotonic() - t0:.0f} s")
    for kind, n in kinds.most_common():
        if kind != "ok":
            print(f"  {kind}: {n}")


def disconnect_run(baud: int) -> None:
    before = pack([record("NiMh"), record("LiPo")], 1024)
    truth = collections.Counter()
    for n in range(0, 700, 4):
        outcome, exc, wanted, after = flash_once(n, baud, Faults(disconnect_after=n), before, record("NiCd"))
        holds = "new" if after == wanted else "previous" if after == before else "MIXED"
        said = getattr(exc, "holds", None) if exc else "new"
        if exc is not None and said is None:
            said = "either" if isinstance(exc, CommitUncertain) else "previous"
        right = said == holds or (said == "either" and holds in ("new", "previous"))
        truth[(outcome, said, holds, "true" if right else "FALSE")] += 1
    print(f"link dies after N received bytes (N = 0..700 step 4), {sum(truth.values())} trials:")
    for (outcome, said, holds, right), k in sorted(truth.items()):
        print(f"  {k:4d} x {outcome:<16} said {said:<8} holds {holds:<8} {right}")


def main() -> None:
    flashes = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    baud = int(sys.argv[2]) if len(sys.argv) > 2 else 115200
    ber_run(flashes, baud)
    disconnect_run(baud)


if __name__ == "__main__":
    main()
