"""The host side of a charger running the ZUML firmware (or the virtual charger): ``client``
(``ChargerClient``: requests, telemetry, the EEPROM written and verified), ``calibration`` (the B6's
calibration from the PC) and ``flashing`` (one macro into an EEPROM image).

May import: ``device.errors``, ``device.links``, and what ``device`` may."""
