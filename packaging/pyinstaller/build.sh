#!/usr/bin/env bash
# Build the frozen Linux bundle: dist/zuml-studio-VERSION-linux-ARCH.tar.gz, a onedir folder with
# zuml-studio (the IDE), zuml (the command line), _internal/ and linux/ (install.sh, desktop file,
# metainfo, icons, udev rule).
#
# It builds from a clean, non-editable install: the wheel is built from a copy of the sources and
# installed into a fresh venv with the pinned dependencies, so the bundle holds exactly what a user's
# pip install would. Build releases on the oldest distribution to support (Ubuntu 22.04): the bundle
# needs the glibc it was built against or newer; the last line says which.
#
#   packaging/pyinstaller/build.sh [OUT_DIR]      (default: dist/; PYTHON=python3.11 picks the Python)
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
OUT="$(mkdir -p "${1:-$ROOT/dist}" && cd "${1:-$ROOT/dist}" && pwd)"
PY="${PYTHON:-python3}"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/zuml-bundle.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT
PIP=(--quiet --disable-pip-version-check)

step() { printf '== [%3ds] %s\n' "$SECONDS" "$*" >&2; }

step "copying the sources"
mkdir "$WORK/src"
cp -r "$ROOT/pyproject.toml" "$ROOT/setup.py" "$ROOT/README.md" "$ROOT/LICENSE" "$ROOT/zuml_studio" "$ROOT/resources" \
    "$ROOT/macros" "$ROOT/firmware" "$WORK/src/"
find "$WORK/src" -name __pycache__ -prune -exec rm -rf {} +
# The wheel's build compiles the C simulation engine from firmware/ itself (setup.py): no built copy goes in.
rm -rf "$WORK/src/firmware/build" "$WORK/src/zuml_studio/sim/_engine"
# The wheel's build compiles the catalogues itself (setup.py); a stale in-tree .mo must not win.
find "$WORK/src/resources/locale" -name "*.mo" -delete

step "building the wheel"
"$PY" -m pip wheel "${PIP[@]}" --no-deps "$WORK/src" -w "$WORK/wheel"
WHEEL="$(ls "$WORK"/wheel/zuml_studio-*.whl)"
VERSION="$(basename "$WHEEL" | cut -d- -f2)"

step "installing it into a clean venv (dependencies pinned by requirements.lock)"
"$PY" -m venv "$WORK/venv"
"$WORK/venv/bin/python" -m pip install "${PIP[@]}" --constraint "$ROOT/requirements.lock" "$WHEEL" \
    -r "$HERE/requirements.txt"

if ! lacking="$("$WORK/venv/bin/python" -m zuml_studio.ui.base.qt_platform_libs)"; then
    # PyInstaller bundles the X11 libraries it finds here; those missing here, users will need.
    printf 'warning: the bundle will lack what this machine lacks; install it here and rebuild:\n%s\n' \
        "$lacking" >&2
fi

step "freezing"
(cd "$WORK" && "$WORK/venv/bin/pyinstaller" --noconfirm --clean --log-level WARN \
    --distpath "$WORK/dist" --workpath "$WORK/build" "$HERE/zuml-studio.spec")
BUNDLE="$WORK/dist/zuml-studio"
cp -r "$ROOT/packaging/linux" "$BUNDLE/linux"
cp "$ROOT/LICENSE" "$BUNDLE/"

NAME="zuml-studio-$VERSION-linux-$(uname -m)"
step "packing $OUT/$NAME.tar.gz"
mv "$BUNDLE" "$WORK/dist/$NAME"
tar -C "$WORK/dist" -czf "$OUT/$NAME.tar.gz" "$NAME"

"$WORK/venv/bin/python" "$HERE/glibc_needed.py" "$WORK/dist/$NAME"
echo "$OUT/$NAME.tar.gz"
