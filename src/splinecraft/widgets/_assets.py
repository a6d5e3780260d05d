"""Locate and load the widgets' ES modules and stylesheet (plain files in ``js/``, no bundler).

In an editable install (``pip install -e .``) the modules are read from ``<repo>/js``; an installed wheel
carries them in ``splinecraft/widgets/static`` (``pyproject.toml`` force-includes ``js`` there).

anywidget loads a widget's ES module from one string, where relative imports cannot resolve, so
:func:`load_esm` links the entry module with everything it imports: every imported module (found by its
``import { ... } from "./name.js";`` lines, recursively) is emitted once, dependencies first, as

    const __sc_name = (() => { <module body without import lines and export keywords>; return { exports }; })();

and each import line becomes ``const { a, b: c } = __sc_name;``. Modules keep their own scope (no name
clashes between them), and the files themselves stay valid ES modules that node can import for unit
tests. Supported module syntax: ``import { a, b as c } from "./x.js";`` and ``export`` in front of
``function``, ``async function``, ``class``, ``const`` and ``let`` declarations; the entry module keeps
its ``export default``.
"""
from __future__ import annotations

import re
from functools import lru_cache
from pathlib import Path

__all__ = ["static_dir", "load_esm", "load_css", "module_order"]

_IMPORT = re.compile(r'^import\s*\{([^}]*)\}\s*from\s*"\./([\w.-]+\.js)";[ \t]*$', re.MULTILINE)
_EXPORT = re.compile(r"^export\s+(?:async\s+)?(?:function\*?|class|const|let)\s+([A-Za-z_$][\w$]*)", re.MULTILINE)
_EXPORT_KEYWORD = re.compile(r"^export\s+(?=(?:async\s+)?(?:function|class|const|let)\b)", re.MULTILINE)
_OTHER_EXPORT = re.compile(r"^export\s+(?!default\b)(?!(?:async\s+)?(?:function|class|const|let)\b)", re.MULTILINE)


def static_dir() -> Path:
    """The directory holding the widgets' ES modules and ``widgets.css``.

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


def _imports(source: str) -> list:
    return [match.group(2) for match in _IMPORT.finditer(source)]


def module_order(name: str, folder: Path | None = None) -> list:
    """The modules ``name`` needs, dependencies first, ``name`` last; raises on an import cycle."""
    folder = folder or static_dir()
    order, visiting = [], []

    def visit(module):
        if module in order:
            return
        if module in visiting:
            raise RuntimeError(f"import cycle among the widget modules: {' -> '.join(visiting + [module])}")
        visiting.append(module)
        for dependency in _imports((folder / module).read_text(encoding="utf-8")):
            visit(dependency)
        visiting.pop()
        order.append(module)

    visit(name)
    return order


def _variable(module: str) -> str:
    return "__sc_" + re.sub(r"\W", "_", module[:-3])


def _bind_imports(source: str) -> str:
    """Replace each ``import { a, b as c } from "./x.js";`` by ``const { a, b: c } = __sc_x;``."""
    def bind(match):
        names = [part.strip() for part in match.group(1).split(",") if part.strip()]
        bindings = [re.sub(r"^(\S+)\s+as\s+(\S+)$", r"\1: \2", item) for item in names]
        return f"const {{ {', '.join(bindings)} }} = {_variable(match.group(2))};"

    return _IMPORT.sub(bind, source)


def _wrapped(module: str, source: str) -> str:
    if _OTHER_EXPORT.search(source) or re.search(r"^export\s+default\b", source, re.MULTILINE):
        raise RuntimeError(f"{module}: only 'export function/class/const/let' can be linked into a widget")
    exported = _EXPORT.findall(source)
    body = _bind_imports(_EXPORT_KEYWORD.sub("", source)).rstrip()
    return (f"// ---- {module} ----\nconst {_variable(module)} = (() => {{\n{body}\n"
            f"return {{ {', '.join(exported)} }};\n}})();\n// ---- end {module} ----\n")


@lru_cache(maxsize=None)
def load_esm(name: str) -> str:
    """Source of the ES module ``name`` (e.g. ``"spline_editor.js"``) linked with every module it imports."""
    folder = static_dir()
    order = module_order(name, folder)
    parts = [_wrapped(module, (folder / module).read_text(encoding="utf-8")) for module in order[:-1]]
    parts.append(_bind_imports((folder / name).read_text(encoding="utf-8")))
    return "\n".join(parts)


@lru_cache(maxsize=None)
def load_css() -> str:
    """The shared stylesheet ``widgets.css``."""
    return (static_dir() / "widgets.css").read_text(encoding="utf-8")
