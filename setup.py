"""What pyproject.toml cannot declare: the source tree's data folders mapped into the package, and
the translation catalogues compiled into it.

``resources/`` (chemistry and charger tables, templates, the icon, the catalogues' sources) becomes
``zuml_studio.resources`` and ``macros/`` (the standard macros) ``zuml_studio.macros``, in the wheel and
in an editable install alike, so the installed package never needs the source tree. Each
``resources/locale/LANG/LC_MESSAGES/zuml_studio.po`` becomes its ``.mo`` beside it in the build, so the
wheel (and the bundle frozen from it) ships every language; an editable install, which has no build
step, compiles them in memory at start (`zuml_studio.i18n`).

The C simulation engine (the firmware's core with the models of firmware/host/model/, the sources listed in
firmware/host/engine.sources) is compiled into ``zuml_studio/sim/_engine/libzuml_engine.so``: in the build for
a wheel, in the source tree for an editable install. Without a C compiler the build warns and the app runs
the Python interpreter, the reference, in its place (`zuml simulate` says which engine ran).
"""
import os
import shlex
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import find_packages, setup
from setuptools.command.build_py import build_py

DATA_FOLDERS = {"zuml_studio.resources": "resources", "zuml_studio.macros": "macros"}
CATALOGUES = "resources/locale/*/LC_MESSAGES/zuml_studio.po"
ENGINE = "zuml_studio/sim/_engine/libzuml_engine.so"
# -ffp-contract=off, no fast-math: the C models must do the Python's double operations exactly
ENGINE_FLAGS = ["-std=c99", "-O2", "-fPIC", "-shared", "-ffp-contract=off", "-fno-fast-math"]


def build_engine(target: Path) -> None:
    """Compile the C simulation engine to ``target``; a loud warning (no failure) when it cannot be."""
    firmware = Path(__file__).parent / "firmware"
    try:
        sources = [str(firmware / line) for line in (firmware / "host" / "engine.sources").read_text().split()]
    except OSError as exc:
        print(f"WARNING: the C simulation engine was not built (no sources: {exc}); ZUML Studio will simulate "
              "with the slower Python interpreter.", file=sys.stderr)
        return
    compiler = shlex.split(os.environ.get("CC") or sysconfig.get_config_var("CC") or "cc")
    if not compiler or shutil.which(compiler[0]) is None:
        compiler = ["gcc"] if shutil.which("gcc") else ["cc"]
    target.parent.mkdir(parents=True, exist_ok=True)
    target.unlink(missing_ok=True)      # never a stale engine (an in-tree build/ keeps the last one) for these sources
    try:
        done = subprocess.run(compiler + ENGINE_FLAGS + ["-o", str(target)] + sources + ["-lm"],
                              capture_output=True, text=True)
        error = (done.stderr.strip() or f"exit status {done.returncode}") if done.returncode else ""
    except OSError as exc:
        error = str(exc)
    if error:
        print(f"WARNING: the C simulation engine was not built ({' '.join(compiler)}: {error.strip()}); "
              "ZUML Studio will simulate with the slower Python interpreter. Install a C compiler "
              "(apt-get install gcc) and reinstall.", file=sys.stderr)


class BuildPyWithCatalogues(build_py):
    def run(self) -> None:
        super().run()
        build_engine(Path(__file__).parent / ENGINE if self.editable_mode else Path(self.build_lib) / ENGINE)
        from babel.messages.mofile import write_mo
        from babel.messages.pofile import read_po

        for po in sorted(Path(__file__).parent.glob(CATALOGUES)):
            with po.open("rb") as fh:
                catalog = read_po(fh)
            if any(message.fuzzy for message in catalog if message.id):
                raise SystemExit(f"{po}: fuzzy entries; translate them (./dev i18n) before building")
            relative = po.relative_to(Path(__file__).parent / "resources").with_suffix(".mo")
            target = Path(self.build_lib) / "zuml_studio" / "resources" / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            with target.open("wb") as fh:
                write_mo(fh, catalog, use_fuzzy=False)


def platform_wheel() -> type:
    """The wheel carries the engine's library: one platform's, for any Python 3 (it does not use Python's C API)."""
    try:
        from setuptools.command.bdist_wheel import bdist_wheel
    except ImportError:                 # setuptools < 70.1
        from wheel.bdist_wheel import bdist_wheel

    class PlatformWheel(bdist_wheel):
        def finalize_options(self) -> None:
            super().finalize_options()
            self.root_is_pure = False

        def get_tag(self) -> tuple[str, str, str]:
            return "py3", "none", super().get_tag()[2]

    return PlatformWheel


if sys.argv[1:] == ["--engine-only"]:       # ./dev: the engine of an editable install, rebuilt when its sources change
    build_engine(Path(__file__).parent / ENGINE)
else:
    setup(packages=find_packages(include=["zuml_studio*"]) + list(DATA_FOLDERS),
          package_dir=DATA_FOLDERS,
          cmdclass={"build_py": BuildPyWithCatalogues, "bdist_wheel": platform_wheel()})
