"""The battery's passport chip, emulated for the virtual charger: it answers every 8-byte request with the
32 bytes of protocol/passport.py, keeps TEMP live and its check right, and lets the charger write only what
a battery lets it (docs/protocol.md, *Battery passport*)."""
from __future__ import annotations

import math
from typing import Callable

from ..domain.chemistry import load_chemistry
from ..domain.units import MAH_PER_AH
from ..protocol.passport import (ERROR_SECTION, MAGIC, OWN_BYTES, PAGE_SIZE, VERSION, AnswerError, BadRequest,
                                 Passport, akk_code, akk_name, check_word, error_answer, parse_request)


class PassportChip:
    """The battery's side: holds the 32 bytes, keeps TEMP live and the check right, and lets the
    charger write only the error section (``factory``: SERIAL, VENDOR, TYPE and V_LIMIT too)."""

    def __init__(self, passport: Passport, temp_source: Callable[[], float] | None = None, *,
                 factory: bool = False):
        self._image = bytearray(passport.to_bytes())
        self._temp_source = temp_source
        self.factory = factory
        self.writes = 0

    def _refresh(self) -> None:
        if self._temp_source is not None:
            t = round(self._temp_source())
            self._image[0x1D] = max(-128, min(127, t)) & 0xFF
        self._image[0] = MAGIC
        self._image[1] = VERSION
        self._image[0x1E:0x20] = check_word(self._image).to_bytes(2, "little")

    @property
    def image(self) -> bytes:
        self._refresh()
        return bytes(self._image)

    @property
    def passport(self) -> Passport:
        return Passport.from_bytes(self.image)

    def answer(self, request: bytes) -> bytes:
        """32 bytes, always: the passport, or an error answer."""
        try:
            op, page, data = parse_request(request)
        except BadRequest as exc:
            return error_answer(exc.code, request)
        if op == "write":
            lo = PAGE_SIZE * page
            changes = [(lo + k, data[k]) for k in range(PAGE_SIZE)
                       if lo + k not in OWN_BYTES and self._image[lo + k] != data[k]]
            if not self.factory and any(at not in ERROR_SECTION for at, _ in changes):
                return error_answer(AnswerError.READ_ONLY, request)
            for at, value in changes:
                self._image[at] = value
            self.writes += 1
        return self.image


def default_passport(chemistry: str, capacity_mah: float, series: int, serial: str = "ZUML-VIRT-0001") -> Passport:
    """What the virtual charger's battery carries: its chemistry, V_LIMIT = the chemistry's absolute
    maximum per cell × cells (rounded up), A_LIMIT = 2C (rounded up, at least 1 A)."""
    code = akk_code(chemistry)
    try:
        chem = load_chemistry(akk_name(code))
        v_limit = min(255, math.ceil(chem.max_v * series - 1e-9))
    except KeyError:
        v_limit = 0
    a_limit = min(255, max(1, math.ceil(2 * capacity_mah / MAH_PER_AH - 1e-9)))
    return Passport(serial, "ZUML", code, 0, 0, v_limit, a_limit, 25)
