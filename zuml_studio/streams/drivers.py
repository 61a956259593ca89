"""The monitor-only chargers ZUML Studio reads, by name, and decoding of a whole capture.

Each driver module (``cheali``, ``icharger_logview``, …) has ``decoder()`` returning a
``StreamDecoder``. These chargers cannot run ZUML macros: every driver here is
``monitor_only`` (the panel disables Flash and Start and says why). ``zuml-tx`` is the ZUML
firmware heard on its TX alone (an iMAX B6 with no receive wire: its macros start from its buttons). ``zuml`` is our own
protocol (``ChargerClient``), listed so a port chooser can offer it beside the others.
"""
from __future__ import annotations

import importlib
import re
from collections.abc import Callable
from dataclasses import dataclass

from ..errors import ZumlError
from ..i18n import N_, _
from ..protocol.messages import Telemetry
from .stream_decoder import StreamDecoder

AUTO = "auto"
ZUML = "zuml"
LISTEN = "zuml-tx"          # the ZUML firmware heard on its TX alone (zuml_stream)


@dataclass(frozen=True)
class Driver:
    name: str
    title: str                  # what the panel calls it; shown as _(title) (N_ marks those with words)
    module: str                 # zuml_studio.device.<module>
    baud: int | None            # default baud (None: USB HID)
    bauds: tuple[int, ...]      # other bauds the charger can be set to
    transport: str              # "serial" | "hid"
    monitor_only: bool = True

    def decoder(self) -> StreamDecoder:
        return importlib.import_module(f"{__package__}.{self.module}").decoder()

    @property
    def vid_pids(self) -> tuple[tuple[int, int], ...]:
        if self.transport != "hid":
            return ()
        return importlib.import_module(f"{__package__}.{self.module}").VID_PIDS


DRIVERS: dict[str, Driver] = {d.name: d for d in (
    Driver("cheali", N_("cheali-charger (iMAX B6 clone, open firmware)"), "cheali", 57600,
           (9600, 19200, 38400, 115200), "serial"),
    Driver("icharger", "Junsi iCharger (106B/206B/208B/306B/3010B)", "icharger_logview", 128000, (9600,), "serial"),
    Driver("imaxb6", N_("iMAX B6 / e-Station (original firmware)"), "imaxb6_serial", 9600, (), "serial"),
    Driver("ultramat", "Graupner Ultramat / Ultra Duo Plus", "ultramat", 9600, (), "serial"),
    Driver(LISTEN, N_("iMAX B6 (ZUML firmware), listening on its TX"), "zuml_stream", 57600, (), "serial"),
    Driver("skyrc", "SkyRC USB (B6 mini, B6AC v2, Q200)", "skyrc_hid", None, (), "hid"),
    Driver("icharger-hid", "Junsi iCharger DUO/X (USB)", "icharger_hid", None, (), "hid"),
    Driver("isdt", "ISDT (C4, A4, Q8) USB", "isdt_hid", None, (), "hid"),
)}
SERIAL_DRIVERS = tuple(d for d in DRIVERS.values() if d.transport == "serial")
HID_DRIVERS = tuple(d for d in DRIVERS.values() if d.transport == "hid")


class CaptureError(ZumlError, ValueError):
    """A capture no driver recognises (the message names what was tried)."""


def driver(name: str) -> Driver:
    try:
        return DRIVERS[name]
    except KeyError:
        raise CaptureError(_("unknown driver {name!r}; drivers: {drivers}").format(
                name=name, drivers=', '.join(DRIVERS))) from None


def hex_dump_reports(data: bytes) -> bytes | None:
    """A text dump of HID reports -> the reports, each padded to 64 bytes; None if ``data``
    is not such a dump. One report per line, hex bytes (spaces optional), an optional
    label (``RX``, ``IN``, …); lines labelled ``TX``/``OUT`` (what the host sent) and ``#``
    comments are left out."""
    if b"\x00" in data or b"$" in data or b"{" in data or b"\x0c" in data:
        return None
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError:
        return None
    out = bytearray()
    for line in text.splitlines():
        tokens = line.split("#", 1)[0].split()
        label = ""
        while tokens and not _is_hex(tokens[0]):
            label = label or tokens[0].upper()
            tokens.pop(0)
        if not tokens or label.startswith(("TX", "OUT", "S=", "R=")):
            continue
        if any(not _is_hex(t) for t in tokens):
            return None
        report = bytes.fromhex("".join(tokens))
        if not 0 < len(report) <= 64:
            return None
        out += report.ljust(64, b"\x00")
    return bytes(out) if out else None


def _is_hex(token: str) -> bool:
    return len(token) % 2 == 0 and all(c in "0123456789abcdefABCDEF" for c in token)


def decode_capture(data: bytes, driver: str | None = None) -> tuple[str, list[Telemetry], int]:
    """Decode a whole raw capture (serial bytes or a HID report dump): (driver name, samples,
    bad records). ``driver=None`` picks the driver that decodes most records (fewest bad on a
    tie); CaptureError when none decodes any."""
    reports = hex_dump_reports(data)
    stream = reports if reports is not None else data
    names = [driver] if driver else [d.name for d in DRIVERS.values()]
    best: tuple[int, int, str, list[Telemetry]] | None = None
    for name in names:
        dec = globals()["driver"](name).decoder()
        samples = dec.feed(stream)
        if best is None or (dec.good, -dec.bad) > (best[0], -best[1]):
            best = (dec.good, dec.bad, name, samples)
    assert best is not None
    good, bad, name, samples = best
    if not good and driver is None:
        raise CaptureError(_("no charger format recognised in {n_data} bytes (tried {names})").format(
                n_data=len(data), names=', '.join(names)))
    return name, samples, bad


# The text forms of the shared samples: iMAX B6 ``tdatetime;iso time;frame hex`` lines, and
# Ultramat frames as hex lines without their 0x0C/0x0D.
# Fields within one line: letting them span lines made every line start scan the rest of a
# capture without ';' (a second per 500 kB of Ultramat hex).
_IMAX_LINE = re.compile(rb"^[^;#\n]*;[^;\n]*;(7b[0-9a-fA-F]{148}7d)\s*$", re.M)
_HEX_LINE = re.compile(rb"^([0-9A-Fa-f]{8,400})\s*$", re.M)
_COMMENT = re.compile(rb"^#[^\n]*\n", re.M)


@dataclass(frozen=True)
class Capture:
    driver: str
    stream: bytes               # the bytes the charger sent, as the driver reads them
    samples: list[Telemetry]
    bad: int


CHOOSE_ON = 1 << 18


def _best(readings, driver: str | None) -> Capture | None:
    """Of (stream, the part of it to decode) pairs, the one that decodes to most samples."""
    best: Capture | None = None
    for stream, part in readings:
        try:
            name, samples, bad = decode_capture(part, driver)
        except CaptureError:
            continue
        if samples and (best is None or (len(samples), -bad) > (len(best.samples), -best.bad)):
            best = Capture(name, stream, samples, bad)
    return best


def _decode_in_pieces(stream: bytes, name: str, progress: Callable[[int, int], None] | None) -> Capture:
    """``decode_capture(stream, name)``, piece by piece (a decoder's samples do not depend on the pieces)."""
    reports = hex_dump_reports(stream)
    stream = reports if reports is not None else stream
    dec = driver(name).decoder()
    samples: list[Telemetry] = []
    for at in range(0, len(stream), CHOOSE_ON):
        samples += dec.feed(stream[at:at + CHOOSE_ON])
        if progress:
            progress(min(at + CHOOSE_ON, len(stream)), len(stream))
    return Capture(name, stream, samples, dec.bad)


def capture_streams(data: bytes) -> list[bytes]:
    """The ways ``data`` can be read as a charger's byte stream: as it is (or the reports of a
    HID dump), without its ``#`` comment lines, and the byte streams of the text forms above."""
    reports = hex_dump_reports(data)
    out = [data if reports is None else reports]
    if _COMMENT.search(data):           # the shared samples name their source in '#' lines
        out.append(_COMMENT.sub(b"", data))
    frames = _IMAX_LINE.findall(data)
    if frames:
        out.append(b"".join(bytes.fromhex(f.decode()) for f in frames))
    lines = _HEX_LINE.findall(data)
    if lines:
        out.append(b"".join(b"\x0c" + line.upper() + b"\r" for line in lines))
    return out


def decode_recording(data: bytes, driver: str | None = None,
                     progress: Callable[[int, int], None] | None = None) -> Capture:
    """A recording file (a raw capture, a HID dump, a text form of one): the reading of its
    ``capture_streams`` that gives most samples (fewest bad on a tie). CaptureError when none
    gives any. A long recording is judged on its first CHOOSE_ON bytes and only the reading
    chosen decodes the rest (every driver on every reading of a day-long capture took minutes),
    in pieces of CHOOSE_ON bytes: ``progress(bytes decoded, bytes)`` after each."""
    streams = capture_streams(data)
    if len(data) > CHOOSE_ON:
        chosen = _best(((stream, stream[:CHOOSE_ON]) for stream in streams), driver)
        whole = _decode_in_pieces(chosen.stream, chosen.driver, progress) if chosen else None
        if whole is not None and whole.samples:
            return whole
    best = _best(((stream, stream) for stream in streams), driver)
    if best is None:
        raise CaptureError(_("no recording recognised in {n_data} bytes (tried {tried})").format(
                n_data=len(data), tried=driver or ', '.join(DRIVERS)))
    return best
