"""Real chargers on this PC's ports (docs/protocol.md, docs/real-chargers.md), in three jobs:

- ``links``: which ports there are (serial, USB-HID), their names checked, what to tell a user refused
  one, and the monitor link that reads a monitor-only charger through its driver;
- ``zuml``: the host side of a charger running the ZUML firmware: ``ChargerClient``, calibration, the
  EEPROM rule of Compile & Flash;
- ``install``: the ISP programmer (avrdude): the firmware install and the macro store through it.

``errors`` is the link's errors, shared by the three. The wire protocol is ``protocol``; the decoders of
monitor-only chargers ``streams``; chargers that are not there ``virtual``.

May import: ``safety``, ``sim``, ``logs``, ``streams``, ``protocol``, ``lang``, ``domain`` and the top-level
modules below; not ``packs`` (beside it) nor ``virtual``, ``cli``, ``ui`` (above). No Qt."""
