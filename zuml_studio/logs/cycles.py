"""A log cut into its cycles, to lay them over each other: one piece per charge phase (or per
discharge phase when there are fewer than two charges), each starting at time 0."""
from __future__ import annotations

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
    # A phase's samples: from its start up to (not including) the next phase's first sample.
    return [(p, log.piece(lo, hi)) for p, (lo, hi) in zip(phases, log.phase_bounds()) if p.state == state]
