"""The simulator: a record's byte code run as the firmware runs it (``program``, ``interpreter``; the C
engine of firmware/ behind ``engine``, held to the Python by a differential test), against models of
batteries and chargers (``battery``, ``cell_pack``, ``batteries``, ``charger_model``, ``delta_peak``), with
why each phase ended (``reasons``), the start checks (``start_check``), and models fitted to real logs and
compared with them (``curve``, ``fit*``, ``measured_r``, ``compare``).

May import: ``logs`` (real curves to fit), ``streams``, ``protocol`` (the start templates' bytes for the C
engine), ``lang``, ``domain`` and the top-level modules below. Nothing here simulates from the AST. No Qt."""
