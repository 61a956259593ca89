"""ZUML Studio: an IDE for chargers programmed in ZUML 2.0. Its packages import each other one way, in the
order docs/architecture.md draws (the language, the protocol, the simulator, the devices, the window)."""

# The application's one reverse-DNS id: the desktop file's name, the AppStream component id and
# Qt's desktop file name (so a Wayland compositor finds the window's icon). packaging/ uses it too.
APP_ID = "io.github.zumlstudio.ZumlStudio"
