"""The Python snippets of the docs: each imports what it uses. Every ```python block of
README.md and docs/*.md is parsed, its imports are run (a renamed or missing module or
name fails here), and every other name it reads must be defined in it, a builtin, or
one of the few placeholders the text around it explains (a user's hand, a classifier's
own functions)."""

from __future__ import annotations

import ast
import builtins
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BLOCK = re.compile(r"```python\n(.*?)```", re.DOTALL)
# Stand-ins the pages explain in words: the user's own hand description and functions.
PLACEHOLDERS = {"PARALLEL_GRIPPER", "ALLEGRO_HAND", "my_hand_mask", "my_estimate", "__file__"}


def _snippets() -> list[tuple[str, str]]:
    found = []
    for page in PAGES:
        for number, code in enumerate(BLOCK.findall(page.read_text()), start=1):
            found.append((f"{page.name}#{number}", code))
    return found


def _defined(tree: ast.Module) -> set[str]:
    """Every name the snippet binds: imports, assignments, functions, classes, their
    arguments, loop and comprehension variables."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            names |= {(a.asname or a.name).split(".")[0] for a in node.names}
        elif isinstance(node, ast.FunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.arg):
            names.add(node.arg)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
    return names


@pytest.mark.parametrize(("where", "code"), _snippets(), ids=[w for w, _ in _snippets()])
def test_a_snippet_imports_what_it_uses(where, code):
    tree = ast.parse(code)
    imports = ast.Module(
        body=[n for n in tree.body if isinstance(n, ast.Import | ast.ImportFrom)],
        type_ignores=[],
    )
    exec(compile(imports, where, "exec"), {})  # the documented imports exist
    read = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}
    undefined = read - _defined(tree) - set(dir(builtins)) - PLACEHOLDERS
    assert not undefined, f"{where} uses names it does not import or define: {sorted(undefined)}"


def test_the_pages_have_snippets():
    assert len(_snippets()) >= 7
