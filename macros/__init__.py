"""The standard macros, mapped into the package as ``zuml_studio.macros`` at build time; listed
through `zuml_studio.data.standard_macros`."""
