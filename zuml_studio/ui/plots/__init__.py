"""What several ui packages show of a run: the stacked V/I/T plot (``stacked_plot``) with its
backdrop, cursor readout, cell curves and PNG export, the data behind it (``plot_data``, the
live ``growing_buffer`` and its min/max ``envelope``, all Qt-free) and the table of the run's
phases (``phase_table``). Used by ui.sim, ui.device, ui.logs and ui.packs; imports only ui.base.
Importing this package loads no Qt."""
