"""Data only (chemistry and charger tables, templates, icons, translations' sources), mapped into
the package as ``zuml_studio.resources`` at build time; read through `zuml_studio.data`."""
