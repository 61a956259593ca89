"""Units of charge and time the package converts between, named once.

The integrators count charge in ampere-seconds (A·s); chargers, logs and people say milliampere-hours
(mAh); the battery models hold capacities in ampere-hours (Ah). Divide by a constant here rather than
write 3.6, 1000 or 3600 where a conversion is meant."""
from __future__ import annotations

AS_PER_MAH = 3.6              # one mAh is 3.6 A·s: mAh = A·s / AS_PER_MAH
MAH_PER_AH = 1000.0           # mAh = Ah * MAH_PER_AH
SECONDS_PER_HOUR = 3600.0     # also the A·s in one Ah: Ah = A·s / SECONDS_PER_HOUR
