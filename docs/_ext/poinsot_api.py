"""Sphinx glue for the poinsot docs.

``.. poinsot-api:: MODULE`` documents a module from its ``__all__``: the module
docstring, a summary table (autosummary) and one autodoc entry per public name
(classes with their documented members). A page per module, each object
documented once, no generated stub files.

Options: ``:exclude: NAME NAME`` (documented on another page), ``:no-module-doc:``.

The ``index`` page's toctrees may name pages other engineers are still writing:
an entry whose file does not exist yet is dropped (with an info message) instead
of failing the ``-W`` build.
"""

from __future__ import annotations

import importlib
import inspect
import re
import types
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import directives
from docutils.statemachine import StringList
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)


def _kind(obj) -> str | None:
    if isinstance(obj, types.ModuleType):
        return None
    if inspect.isclass(obj):
        return "autoexception" if issubclass(obj, BaseException) else "autoclass"
    if inspect.isroutine(obj) or (callable(obj) and hasattr(obj, "__wrapped__")):
        return "autofunction"
    if callable(obj) and getattr(obj, "__doc__", None) and hasattr(obj, "py_func"):  # numba
        return "autofunction"
    return "autodata"


class PoinsotApi(SphinxDirective):
    required_arguments = 1
    option_spec = {"exclude": directives.unchanged, "no-module-doc": directives.flag}

    def run(self):
        modname = self.arguments[0]
        mod = importlib.import_module(modname)
        self.env.note_dependency(inspect.getsourcefile(mod) or "")
        exclude = set(self.options.get("exclude", "").replace(",", " ").split())
        names = getattr(mod, "__all__", None)
        if names is None:
            names = sorted(n for n in vars(mod) if not n.startswith("_"))
        entries = []
        for name in names:
            if name in exclude:
                continue
            kind = _kind(getattr(mod, name))
            if kind is not None:
                entries.append((name, kind))
        lines = [f".. automodule:: {modname}", "   :no-members:", ""]
        if "no-module-doc" in self.options:
            lines = []
        lines += [f".. currentmodule:: {modname}", ""]
        if entries:
            lines += [".. rubric:: Summary", "", ".. autosummary::", "   :nosignatures:", ""]
            lines += [f"   {name}" for name, _ in entries] + [""]
            lines += [".. rubric:: Reference", ""]
        for name, kind in entries:
            lines.append(f".. {kind}:: {name}")
            if kind == "autodata":
                lines.append("   :no-value:")
            lines.append("")
        node = nodes.Element()
        self.state.nested_parse(StringList(lines, source=f"<poinsot-api {modname}>"), 0, node)
        return node.children


_TOCTREE = re.compile(r"```\{toctree\}(.*?)```", re.S)


def _drop_missing_pages(app, docname, source):
    if docname != app.config.root_doc:
        return
    srcdir = Path(app.srcdir)

    def exists(entry: str) -> bool:
        entry = entry.strip()
        if not entry or entry.startswith(":") or "<" in entry or "*" in entry:
            return True
        return any((srcdir / (entry + ext)).is_file() for ext in (".md", ".rst", ".ipynb"))

    def fix(m: re.Match) -> str:
        kept = []
        for line in m.group(1).split("\n"):
            if exists(line):
                kept.append(line)
            else:
                logger.info(f"[poinsot] toctree: page {line.strip()!r} not written yet, skipped")
        return "```{toctree}" + "\n".join(kept) + "```"

    source[0] = _TOCTREE.sub(fix, source[0])


def _reread_root(app, env, added, changed, removed):
    # the root page's toctree depends on which pages exist: read it again every build
    return [app.config.root_doc]


def setup(app):
    app.add_directive("poinsot-api", PoinsotApi)
    app.connect("source-read", _drop_missing_pages)
    app.connect("env-get-outdated", _reread_root)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
