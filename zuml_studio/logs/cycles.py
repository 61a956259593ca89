"""A log cut into its cycles, to lay them over each other: one piece per charge phase (or per
discharge phase when there are fewer than two charges), each starting at time 0."""
from __future__ import annotations

from dataclasses import replace

from .model import Log, Phase


def split_cycles(log: Log) -> list[tuple[Phase, Log]]:
    """[(phase, piece)]; fewer than two phases of either kind: [] (nothing to lay over)."""
    phases = log.phases()
    for state in ("charge", "discharge"):
        chosen = [p for p in phases if p.state == state]
        if len(chosen) >= 2:
            break
    else:
        return []
    pieces = []
    times = [s.time_s for s in log.samples]
    for p in chosen:
        # The phase's samples: from its start up to (not including) the next phase's first sample.
        lo = next(k for k, t in enumerate(times) if t >= p.start_s)
        hi = lo
        while hi < len(times) and log.samples[hi].run == log.samples[lo].run and \
                log.samples[hi].section == state:
            hi += 1
        first = log.samples[lo]
        samples = tuple(replace(s, time_s=s.time_s - first.time_s, mah_in=s.mah_in - first.mah_in,
                                mah_out=s.mah_out - first.mah_out) for s in log.samples[lo:hi])
        pieces.append((p, replace(log, samples=samples, resistance=())))
    return pieces
