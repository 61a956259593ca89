"""The pack's resistance where a log's current stops (the method of docs/validation.md): the voltage fall
per cell and ampere between the last sample with the current on and the first rest sample at least
``delay_s`` after it. One second is short enough that the slow polarisation has barely moved and long
enough that a sample is not read while the current is still falling; a reading later than ``max_delay_s``
(a coarse log) would include the polarisation and is not taken."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# A rest: the current below this share of the current before the step.
_REST_SHARE = 0.1


@dataclass(frozen=True)
class RestStep:
    time_s: float            # the last sample with the current on
    current_a: float         # signed, as logged
    drop_v: float            # voltage before − voltage after (signed like the current)
    delay_s: float           # from the last sample on to the sample read

    def ohm_per_cell(self, cells: int) -> float:
        return self.drop_v / self.current_a / max(cells, 1)


def rest_steps(t: np.ndarray, v: np.ndarray, i: np.ndarray, *, min_current_a: float = 0.05,
               delay_s: float = 1.0, max_delay_s: float = 5.0) -> list[RestStep]:
    """Every place where |current| ≥ ``min_current_a`` falls to a rest (below a tenth of it) and the rest
    lasts until a sample ``delay_s`` to ``max_delay_s`` after the last sample on."""
    t, v, i = (np.asarray(x, float) for x in (t, v, i))
    steps: list[RestStep] = []
    for j in range(1, len(i)):
        on = i[j - 1]
        if abs(on) < min_current_a or abs(i[j]) >= _REST_SHARE * abs(on):
            continue
        for k in range(j, len(i)):
            if abs(i[k]) >= _REST_SHARE * abs(on) or t[k] - t[j - 1] > max_delay_s:
                break
            if t[k] - t[j - 1] >= delay_s:
                steps.append(RestStep(float(t[j - 1]), float(on), float(v[j - 1] - v[k]), float(t[k] - t[j - 1])))
                break
    return steps


def resistance_mohm_per_cell(t: np.ndarray, v: np.ndarray, i: np.ndarray, cells: int) -> float | None:
    """The median of a log's rest steps in mΩ per cell; None where the log has no step to read. Where the
    log samples slower than once a second its first rest sample may straddle the step (the eStation BC6's
    1.5 s samples in docs/validation.md), so the second one is read."""
    period = float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    delay = 1.0 if period <= 1.0 else 2.0 * period
    found = [s.ohm_per_cell(cells) for s in rest_steps(t, v, i, delay_s=delay)]
    return float(np.median(found)) * 1000.0 if found else None
