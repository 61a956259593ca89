"""Ports and the links over them: the port list (``ports``, ``port_info``, ``hid_link``), port names and
URLs checked before pyserial sees them (``port_url``), advice for a refused port (``port_access``), the
monitor link that reads a monitor-only charger (``monitor_link``) and the raw serial monitor's text
(``serial_text``, ``serial_lines``), and opening a serial line (``serial_port``).

May import: ``device.errors`` and what ``device`` may; not ``device.zuml`` or ``device.install``, which use it."""
