"""Chargers that are not there: the virtual charger (``virtual_charger``: the simulator's interpreter behind
the protocol, its battery's passport chip in ``passport_chip``) served on a pty or TCP (``transport``), a
recording played back as a charger (``replay``), and the firmware itself built and run on this PC
(``firmware_sim``; ``simulated_b6``: the simulated iMAX B6 the window starts).

Above ``safety``: the virtual charger refuses a START as a real one does, through the one check.
May import: ``device``, ``packs``, ``safety`` and everything below them; not ``cli`` or ``ui``. No Qt."""
