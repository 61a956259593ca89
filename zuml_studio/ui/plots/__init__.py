"""The plots and tables of a run that several ui packages share."""
