"""The ZUML firmware heard on its TX alone: an iMAX B6 whose 3-pin port is wired to a USB-serial
adapter's RX and nothing to the charger's receive pin (docs/protocol.md, *Listen-only*).

While no host has spoken the firmware sends, unasked, the protocol's own TELEMETRY and EVENT frames
and LCD frames with its display's lines. This decoder takes them as they come: telemetry becomes
samples (the firmware's own sections, phases, run numbers and charge counters, nothing inferred),
events and the display's lines wait in ``take_extras()`` for the reader. Nothing is ever sent.
"""
from __future__ import annotations

from ..protocol.frames import MAX_FRAME, FrameParser
from ..protocol.messages import BY_NAME, DEVICE_TYPES, EVENT, LCD, TELEMETRY, DeviceEvent, PayloadError, Telemetry, unpack_fields
from .stream_decoder import StreamDecoder

MAX_EXTRAS = 1000          # events and display lines a reader has not taken yet (a losing detection candidate)


class ZumlStreamDecoder(StreamDecoder):
    name = "zuml-tx"
    max_record = MAX_FRAME

    def __init__(self) -> None:
        super().__init__()
        self._parser = FrameParser(DEVICE_TYPES)
        self._bad_payloads = 0
        self.lcd = ["", ""]
        self._extras: list[tuple[str, object]] = []

    def feed(self, data: bytes) -> list[Telemetry]:
        out: list[Telemetry] = []
        for frame in self._parser.feed(data):
            try:
                if frame.type == TELEMETRY:
                    out.append(Telemetry.decode(frame.payload))
                elif frame.type == EVENT:
                    self._extras.append(("event", DeviceEvent.decode(frame.payload)))
                elif frame.type == LCD:
                    line = unpack_fields(BY_NAME["LCD"].response, frame.payload)
                    if line["row"] > 1:
                        raise PayloadError(f"LCD row {line['row']}")
                    self.lcd[line["row"]] = line["text"].rstrip()
                    self._extras.append(("lcd", tuple(self.lcd)))
                else:                  # an answer to some other host's request: not for a listener
                    self.skipped += 1
                    continue
            except PayloadError:
                self._bad_payloads += 1
                continue
            self.good += 1
        del self._extras[:-MAX_EXTRAS]
        self.bad = self._parser.bad_frames + self._bad_payloads
        return out

    @property
    def pending(self) -> int:
        return self._parser.pending

    def take_extras(self) -> list[tuple[str, object]]:
        extras, self._extras = self._extras, []
        return extras


def decoder() -> ZumlStreamDecoder:
    return ZumlStreamDecoder()
