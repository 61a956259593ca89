"""The build step pyproject.toml cannot declare: compile the translation catalogues into the package.

Each ``zuml_studio/locale/LANG/LC_MESSAGES/zuml_studio.po`` becomes its ``.mo`` beside it in the
build, so the wheel (and the bundle frozen from it) ships every language. Babel is a build
requirement only; at run time the package reads the ``.mo`` with the standard library's gettext.
"""
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

CATALOGUES = "zuml_studio/locale/*/LC_MESSAGES/zuml_studio.po"


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
            relative = po.relative_to(Path(__file__).parent).with_suffix(".mo")
            target = Path(self.build_lib) / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            with target.open("wb") as fh:
                write_mo(fh, catalog, use_fuzzy=False)


setup(cmdclass={"build_py": BuildPyWithCatalogues})
