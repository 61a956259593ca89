#!/usr/bin/env bash
# Install the ZUML Studio bundle for the current user, under ~/.local (no root needed):
#   ~/.local/lib/zuml-studio/                     the bundle
#   ~/.local/bin/zuml-studio, ~/.local/bin/zuml   links to its programs
#   ~/.local/share/applications/, metainfo/, icons/hicolor/, mime/   desktop file, AppStream data,
#                                                            icons, the .zuml file type
#
#   ./linux/install.sh [BUNDLE_DIR]     from an unpacked bundle (BUNDLE_DIR defaults to this file's ..)
#   ./linux/install.sh --uninstall
# The udev rule that lets you open the charger's serial port needs root; this script prints the
# commands. PREFIX=/some/dir installs there instead of ~/.local.
set -euo pipefail
APP_ID=io.github.zumlstudio.ZumlStudio
HERE="$(cd "$(dirname "$0")" && pwd)"
PREFIX="${PREFIX:-$HOME/.local}"
LIB="$PREFIX/lib/zuml-studio"
SHARE="$PREFIX/share"

refresh_caches() {
    # Optional helpers; a desktop without them rescans on next login.
    command -v update-desktop-database >/dev/null && update-desktop-database -q "$SHARE/applications" || true
    command -v gtk-update-icon-cache >/dev/null && gtk-update-icon-cache -q -t "$SHARE/icons/hicolor" || true
    command -v update-mime-database >/dev/null && update-mime-database "$SHARE/mime" || true
}

if [ "${1:-}" = "--uninstall" ]; then
    rm -rf "$LIB"
    rm -f "$PREFIX/bin/zuml-studio" "$PREFIX/bin/zuml" "$SHARE/applications/$APP_ID.desktop" \
          "$SHARE/metainfo/$APP_ID.metainfo.xml" "$SHARE/icons/hicolor/scalable/apps/$APP_ID.svg" \
          "$SHARE/mime/packages/$APP_ID.xml"
    for size in 48 128 256; do rm -f "$SHARE/icons/hicolor/${size}x${size}/apps/$APP_ID.png"; done
    refresh_caches
    echo "ZUML Studio removed from $PREFIX (your macros and settings in ~/.config/zuml-studio stay)."
    exit 0
fi

BUNDLE="$(cd "${1:-$HERE/..}" && pwd)"
if [ ! -x "$BUNDLE/zuml-studio" ] || [ ! -x "$BUNDLE/zuml" ]; then
    echo "install.sh: $BUNDLE is not a ZUML Studio bundle (no zuml-studio and zuml programs in it)" >&2
    exit 2
fi

mkdir -p "$PREFIX/bin" "$SHARE/applications" "$SHARE/metainfo" "$SHARE/icons/hicolor/scalable/apps" \
    "$SHARE/mime/packages"
# Copy to a fresh folder, then swap: a failed copy never leaves half an installation.
rm -rf "$LIB.new"
mkdir -p "$(dirname "$LIB")"
cp -a "$BUNDLE" "$LIB.new"
rm -rf "$LIB"
mv "$LIB.new" "$LIB"
ln -sf "$LIB/zuml-studio" "$PREFIX/bin/zuml-studio"
ln -sf "$LIB/zuml" "$PREFIX/bin/zuml"

# A desktop session's PATH may lack ~/.local/bin: the installed entry names the program by its path.
sed -e "s|^Exec=zuml-studio |Exec=$LIB/zuml-studio |" -e "s|^TryExec=zuml-studio$|TryExec=$LIB/zuml-studio|" \
    "$HERE/$APP_ID.desktop" > "$SHARE/applications/$APP_ID.desktop"
install -m 644 "$HERE/$APP_ID.metainfo.xml" "$SHARE/metainfo/"
install -m 644 "$HERE/$APP_ID.mime.xml" "$SHARE/mime/packages/$APP_ID.xml"
install -m 644 "$LIB/_internal/zuml_studio/resources/icon.svg" "$SHARE/icons/hicolor/scalable/apps/$APP_ID.svg"
for size in 48 128 256; do
    mkdir -p "$SHARE/icons/hicolor/${size}x${size}/apps"
    install -m 644 "$HERE/icons/$size.png" "$SHARE/icons/hicolor/${size}x${size}/apps/$APP_ID.png"
done
refresh_caches

echo "ZUML Studio installed in $LIB; start it from the applications menu or run: zuml-studio"
case ":$PATH:" in
    *":$PREFIX/bin:"*) ;;
    *) echo "Add $PREFIX/bin to your PATH to run zuml and zuml-studio from a shell." ;;
esac
cat <<EOF

To let ZUML Studio open the charger's USB-serial port without joining the dialout group, install
the udev rule (once, as root), then replug the charger:
  sudo install -m 644 "$LIB/linux/60-zuml-studio-serial.rules" /etc/udev/rules.d/
  sudo udevadm control --reload-rules && sudo udevadm trigger
EOF
