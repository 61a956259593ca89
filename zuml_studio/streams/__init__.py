"""What a charger sends, decoded to telemetry samples: one module per family of monitor-only chargers
(``cheali``, ``icharger_logview``, ``icharger_hid``, ``imaxb6_serial``, ``isdt_hid``, ``skyrc_hid``,
``ultramat``) and the ZUML firmware heard on its TX alone (``zuml_stream``), on what they share
(``stream_decoder``, ``frame_scanner``, ``charge_counter``), with the registry by name (``drivers``) and
the guess of which one is on a port (``autodetect``). Bytes in, samples out: the live link
(``device.links.monitor_link``) and the log readers (``logs``) both use them, so they sit below both.

May import: ``protocol`` (the telemetry sample, the frames), ``lang``, ``domain`` and the top-level modules
below. No ports, no threads, no Qt."""
