"""Locate and load the widgets' ES modules and stylesheet (plain files in ``js/``, no bundler).

In an editable install (``pip install -e .``) the modules are read from ``<repo>/js``; an installed wheel
carries them in ``splinecraft/widgets/static`` (``pyproject.toml`` force-includes ``js`` there).

anywidget loads a widget's ES module from a string, where relative imports cannot resolve, so
:func:`load_esm` inlines the shared helper module ``common.js`` in place of its ``import ... from
"./common.js"`` line. The files themselves stay valid ES modules (node can import them for unit tests).
"""
from __future__ import annotations

import re
from functools import lru_cache
from pathlib import Path

__all__ = ["static_dir", "load_esm", "load_css"]

_IMPORT_COMMON = re.compile(r'^import\s*\{[^}]*\}\s*from\s*"\./common\.js";\s*$', re.MULTILINE)


def static_dir() -> Path:
    """The directory holding ``common.js``, ``spline_editor.js``, ``trace_explorer.js``, ``widgets.css``.

    Prefers the repository's ``js/`` (editable install, two levels above the ``src`` package), then the
    packaged ``static`` directory next to this module.
    """
    here = Path(__file__).resolve().parent
    candidates = [here.parents[2] / "js", here / "static"]
    for candidate in candidates:
        if (candidate / "common.js").is_file():
            return candidate
    raise FileNotFoundError(
        "splinecraft widget assets not found; looked in " + ", ".join(str(c) for c in candidates)
    )


@lru_cache(maxsize=None)
def load_esm(name: str) -> str:
    """Source of the ES module ``name`` (e.g. ``"spline_editor.js"``) with ``common.js`` inlined."""
    folder = static_dir()
    source = (folder / name).read_text(encoding="utf-8")
    common = (folder / "common.js").read_text(encoding="utf-8")
    common = re.sub(r"^export\s+", "", common, flags=re.MULTILINE)
    inlined, count = _IMPORT_COMMON.subn(lambda _m: f"// ---- inlined common.js ----\n{common}\n// ---- end common.js ----", source)
    if count != 1:
        raise RuntimeError(f"{name}: expected exactly one import from ./common.js, found {count}")
    return inlined


@lru_cache(maxsize=None)
def load_css() -> str:
    """The shared stylesheet ``widgets.css``."""
    return (static_dir() / "widgets.css").read_text(encoding="utf-8")
