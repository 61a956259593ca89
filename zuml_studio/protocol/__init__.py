"""The wire protocol of a charger running the ZUML firmware (docs/protocol.md), bytes only, no ports and
no threads: the CRC (``crc``), frames and their resynchronising parser (``frames``), the one table of
message types and payload layouts with the telemetry sample and event they carry (``messages``), and the
battery passport's requests and answers (``passport``).

May import: ``lang`` (the passport names battery types as the language does), ``domain`` and the top-level
modules below. The host side (``device.zuml``), the virtual charger (``virtual``), the simulator's C
engine (start templates as the firmware stores them) and the safety check all use it. No Qt."""
