"""The concepts every other package shares, at the bottom of the package order (docs/architecture.md):
chemistries and their limits (``chemistry``), the start templates and their table (``start_templates``),
the three tasks (``tasks``), the telemetry columns a run writes (``samples``); new shared concepts (units,
end reasons, the root of the package's errors) go here.

May import: only the top-level modules below it (``i18n``, ``data``, ``data_error``, ``file_errors``,
``user_dirs``, ``recovery``, ``macro_file``). No Qt."""
