"""The concepts every other package shares, at the bottom of the package order (docs/architecture.md):
chemistries and their limits (``chemistry``), the start templates and their table (``start_templates``),
the three tasks (``tasks``), the telemetry columns a run writes (``samples``) and the CSV columns of every
file the package writes (``csv_columns``), units (``units``), the ways a run ends (``end_reasons``); new
shared concepts go here. The root of the package's errors is below it, in ``zuml_studio.errors``.

May import: only the top-level modules below it (``errors``, ``i18n``, ``data``, ``data_error``,
``file_errors``, ``user_dirs``, ``recovery``, ``macro_file``). No Qt."""
