"""What pyproject.toml cannot declare: the source tree's data folders mapped into the package, and
the translation catalogues compiled into it.

``resources/`` (chemistry and charger tables, templates, the icon, the catalogues' sources) becomes
``zuml_studio.resources`` and ``macros/`` (the standard macros) ``zuml_studio.macros``, in the wheel and
in an editable install alike, so the installed package never needs the source tree. Each
``resources/locale/LANG/LC_MESSAGES/zuml_studio.po`` becomes its ``.mo`` beside it in the build, so the
wheel (and the bundle frozen from it) ships every language; an editable install, which has no build
step, compiles them in memory at start (`zuml_studio.i18n`).
"""
from pathlib import Path

from setuptools import find_packages, setup
from setuptools.command.build_py import build_py

DATA_FOLDERS = {"zuml_studio.resources": "resources", "zuml_studio.macros": "macros"}
CATALOGUES = "resources/locale/*/LC_MESSAGES/zuml_studio.po"


class BuildPyWithCatalogues(build_py):
    def run(self) -> None:
        super().run()
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


setup(packages=find_packages(include=["zuml_studio*"]) + list(DATA_FOLDERS),
      package_dir=DATA_FOLDERS,
      cmdclass={"build_py": BuildPyWithCatalogues})
