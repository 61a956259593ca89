"""Charge in and out from a charger's capacity counter, sample by sample: one rule for the
live drivers (``stream_decoder``) and the log readers (``logs/charge.py``).

Chargers count the charge of the phase they are in and start again at 0 for the next one;
the counter is signed (negative: discharged). A fall in magnitude or a change of sign starts
a new count: what the previous count reached is banked into in or out. A fall of up to
``JITTER_MAH`` is rounding, not a new count."""
from __future__ import annotations

JITTER_MAH = 1.0


class ChargeCounter:
    def __init__(self) -> None:
        self._bank_in = 0.0
        self._bank_out = 0.0
        self._prev = 0.0

    def add(self, counter_mah: float) -> tuple[float, float]:
        """The next counter value -> cumulative (mAh in, mAh out)."""
        c, prev = counter_mah, self._prev
        if (prev > 0 and c < 0) or (prev < 0 and c > 0) or abs(c) < abs(prev) - JITTER_MAH:
            self._bank_in += max(prev, 0.0)
            self._bank_out += max(-prev, 0.0)
        self._prev = c
        return self._bank_in + max(c, 0.0), self._bank_out + max(-c, 0.0)

    @property
    def totals(self) -> tuple[float, float]:
        return self._bank_in + max(self._prev, 0.0), self._bank_out + max(-self._prev, 0.0)
