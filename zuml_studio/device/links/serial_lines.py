"""The serial monitor's view of what came in, as Arduino IDE users know it: optionally each line
with the time it arrived, and in hex a line per burst (bytes arriving after a pause start a new
line: a charger's frames stand apart). Qt-free; the monitor keeps the bursts and re-renders them
when a view option changes."""
from __future__ import annotations

import time
from dataclasses import dataclass

from .serial_text import as_hex, as_text

BURST_GAP_S = 0.03      # bytes after this pause begin a new line in hex (a frame at 115200 baud takes ~2 ms)


def stamp(when: float) -> str:
    """``12:34:56.789 → ``: the local time a line began."""
    whole = time.localtime(when)
    return time.strftime("%H:%M:%S", whole) + f".{int(when * 1000) % 1000:03d} → "


@dataclass
class MonitorLines:
    """Renders bursts (``when``, ``data``) one after another, remembering where the last one ended."""
    hex_mode: bool = False
    timestamps: bool = False
    _at_line_start: bool = True
    _last: float | None = None

    def render(self, when: float, data: bytes) -> str:
        if self.hex_mode:
            out = ""
            if self._last is None or when - self._last > BURST_GAP_S:
                out = ("" if self._at_line_start else "\n") + (stamp(when) if self.timestamps else "")
            self._last = when
            self._at_line_start = False
            return out + as_hex(data)
        self._last = when
        text = as_text(data)
        if not self.timestamps:
            if text:
                self._at_line_start = text.endswith("\n")
            return text
        out = []
        for line in text.splitlines(keepends=True):
            out.append((stamp(when) if self._at_line_start else "") + line)
            self._at_line_start = line.endswith("\n")
        return "".join(out)

    def render_all(self, bursts: list[tuple[float, bytes]]) -> str:
        """From the first burst on (a view option changed)."""
        self._at_line_start, self._last = True, None
        return "".join(self.render(when, data) for when, data in bursts)
