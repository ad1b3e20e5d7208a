"""Write the API reference and the command-line page from the package itself.

Called from ``conf.py`` before Sphinx reads the sources. The pages list what the
package exports, so a name added to ``optri.__all__`` or to a public subpackage's
``__all__``, a new public subpackage, or a new ``optri`` command is documented on
the next build without editing any page. Files are rewritten only when their text
changes, which keeps incremental builds incremental.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import sys
import types
from pathlib import Path
from typing import Any

#: modules of the package that are not part of the Python API reference
SKIPPED = {"optri.cli", "optri.__main__"}


def public_modules() -> list[str]:
    """``optri.X`` for every public module and subpackage directly under optri."""
    import optri

    found = [
        f"optri.{info.name}"
        for info in pkgutil.iter_modules(optri.__path__)
        if not info.name.startswith("_")
    ]
    return sorted(name for name in found if name not in SKIPPED)


def exported(module: types.ModuleType) -> list[str]:
    """The module's ``__all__``; without one, its public functions and classes."""
    names = getattr(module, "__all__", None)
    if names is None:
        names = [
            name
            for name, obj in vars(module).items()
            if not name.startswith("_")
            and (inspect.isfunction(obj) or inspect.isclass(obj))
            and getattr(obj, "__module__", "").startswith(module.__name__)
        ]
    return [name for name in names if not name.startswith("__")]


def _directive(qualified: str, obj: Any) -> str:
    # a name that is also a module's (the function optri.batch, the module optri.batch)
    # is indexed once, as the module; its full entry stays on its module's page
    shadowed = "   :no-index:\n" if qualified in sys.modules else ""
    if inspect.isclass(obj):
        return f".. autoclass:: {qualified}\n   :members:\n   :show-inheritance:\n{shadowed}"
    if inspect.isroutine(obj):
        return f".. autofunction:: {qualified}\n{shadowed}"
    return f".. autodata:: {qualified}\n{shadowed}"


def _title(text: str, mark: str = "=") -> str:
    return f"{text}\n{mark * len(text)}\n"


def _summary(obj: Any) -> str:
    doc = inspect.getdoc(obj) or ""
    return doc.strip().splitlines()[0] if doc.strip() else ""


def top_level_page() -> str:
    """The page of ``optri`` itself: every name of ``optri.__all__``."""
    import optri

    parts = [
        _title("optri"),
        ".. automodule:: optri\n   :no-members:\n",
        f"``optri.__version__`` is ``{optri.__version__!r}``.\n",
    ]
    for name in exported(optri):
        obj = getattr(optri, name)
        if isinstance(obj, types.ModuleType):
            parts.append(f"* :doc:`optri.{name} <{obj.__name__}>`: {_summary(obj)}\n")
        elif not (inspect.isclass(obj) or inspect.isroutine(obj)):
            home = _home(name, obj)
            parts.append(f".. py:data:: optri.{name}\n\n   See :py:data:`{home}.{name}`.\n")
        else:
            parts.append(_directive(f"optri.{name}", obj))
    return "\n".join(parts)


def _home(name: str, obj: Any) -> str:
    """The public module whose ``__all__`` exports ``obj`` as ``name``."""
    for module in public_modules():
        mod = importlib.import_module(module)
        if name in exported(mod) and getattr(mod, name) is obj:
            return module
    return "optri"


def module_page(name: str) -> str:
    """The page of one public module: its docstring and every name it exports."""
    import optri

    module = importlib.import_module(name)
    options = "   :no-members:\n"
    parts = [_title(f"``{name}``"), f".. automodule:: {name}\n{options}"]
    if name == "optri.config":  # its tunables are documented attributes, not __all__
        parts.append(f".. automodule:: {name}\n   :members:\n   :ignore-module-all:\n")
        parts[1] = ""
    again = []
    for item in exported(module):
        obj = getattr(module, item)
        top = getattr(optri, item, None)
        documented_above = inspect.isclass(obj) or inspect.isroutine(obj)
        if top is obj and documented_above:  # data is documented here, where it lives
            again.append(f"* :py:obj:`optri.{item}`: {_summary(obj)}")
        elif name != "optri.config":
            parts.append(_directive(f"{name}.{item}", obj))
    if again:
        parts.append(".. rubric:: Also in the top-level namespace\n\n" + "\n".join(again) + "\n")
    return "\n".join(part for part in parts if part)


def cli_page() -> str:
    """The ``optri`` command and each subcommand's ``--help``."""
    import click

    from optri.cli import main

    settings = {**main.context_settings, "max_content_width": 88, "terminal_width": 88}
    root = click.Context(main, info_name="optri", **settings)
    parts = [
        _title("Command line"),
        "``optri`` (also ``python -m optri``) is installed with the package. Each "
        "command's ``--help``, as printed by the installed version:\n",
        _literal(main.get_help(root)),
    ]
    for name in sorted(main.commands):
        command = main.commands[name]
        ctx = click.Context(command, info_name=name, parent=root, max_content_width=88)
        parts += [_title(f"optri {name}", "-"), _literal(command.get_help(ctx))]
    return "\n".join(parts)


def _literal(text: str) -> str:
    body = "\n".join(f"   {line}" if line else "" for line in text.splitlines())
    return f".. code-block:: text\n\n{body}\n"


def reference_pages() -> dict[str, str]:
    """Relative path -> text of every generated page."""
    modules = public_modules()
    toc = "\n".join(f"   {name}" for name in ["optri", *modules])
    index = (
        _title("API reference")
        + "\nGenerated from the docstrings: the top-level namespace first, then each "
        "public module and subpackage.\n\n.. toctree::\n   :maxdepth: 1\n\n" + toc + "\n"
    )
    pages = {"api/index.rst": index, "api/optri.rst": top_level_page(), "api/cli.rst": cli_page()}
    for name in modules:
        pages[f"api/{name}.rst"] = module_page(name)
    return pages


def write_reference(docs: Path) -> None:
    """Write the generated pages under ``docs``; remove stale ones from ``docs/api``."""
    pages = reference_pages()
    for relative, text in pages.items():
        path = docs / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    for old in (docs / "api").glob("*.rst"):
        if f"api/{old.name}" not in pages:
            old.unlink()
