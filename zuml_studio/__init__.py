"""ZUML Studio."""

# The application's one reverse-DNS id: the desktop file's name, the AppStream component id and
# Qt's desktop file name (so a Wayland compositor finds the window's icon). packaging/ uses it too.
APP_ID = "io.github.zumlstudio.ZumlStudio"
