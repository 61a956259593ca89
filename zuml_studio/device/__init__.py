"""The device link: ZUML Studio <-> a charger over a serial line (docs/protocol.md).

No Qt here. Layers, bottom up:

- ``crc``: CRC-16/MODBUS, as cheali-charger uses for its EEPROM blocks.
- ``frames``: ``A5 LEN TYPE SEQ PAYLOAD CRC16`` and an incremental parser that resyncs.
- ``messages``: the one table of message types and their payload layouts.
- ``passport``: the battery passport of docs/zuml-2.0.md §4 (8-byte request, 32-byte answer) and the lockout.
- ``virtual_charger`` + ``transport``: a charger that runs the simulator behind a pty or TCP port.
- ``client``: ``ChargerClient``, used by the CLI and the GUI.
- ``errors``, ``ports``.
"""
