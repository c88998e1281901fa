"""Every ```python block of the README, the guide (docs/*.md) and this package's README, run,
so that an example that no longer works fails here instead of in a reader's session.

How the blocks are run:

- A block that imports rattle starts a session; a block that does not continues the session of
  the blocks above it on the same page, as a reader pastes them one after the other. A session
  is one test, its blocks run in order in one namespace (``__name__`` is ``"__main__"``, as in
  a script), in a temporary directory holding a copy of ``data/scenes``.
- A session that needs an optional package (one it imports, pandas for ``.to_pandas()``,
  xarray for ``.to_xarray()``) is skipped with ``pytest.importorskip`` of that package when it
  is not installed; matplotlib draws on its non-interactive backend, so ``plt.show()``
  returns at once.
- The directives above a fence (``crates/compare/tests/docs_snippets.rs`` describes them)
  apply here too: ``<!-- test: OLD => NEW -->`` runs the block with ``OLD`` replaced by
  ``NEW`` (a small size for a big study; it must match), and ``<!-- test: not run: REASON -->``
  leaves the block out of its session, for the reason given.
"""

import ast
import os
import re
import shutil
import sys
from pathlib import Path

import pytest
from conftest import REPOSITORY, SCENES

PAGES = [
    REPOSITORY / "README.md",
    *sorted((REPOSITORY / "docs").glob("*.md")),
    REPOSITORY / "crates" / "python" / "README.md",
]

#: The packages a call needs beyond its own imports.
NEEDED_BY_CALLS = {".to_pandas(": "pandas", ".to_xarray(": "xarray"}

#: Modules that come with Python or with the package: never skipped for (the standard
#: library's names are listed by Python 3.10 and later; these are the ones the pages use).
PRESENT = {"rattle", "numpy", "collections", "json", "math", "os", "pathlib", "sys"} | set(
    getattr(sys, "stdlib_module_names", ())
)


class Block:
    """One fenced block of a page."""

    def __init__(self, page, line, language, code, directives):
        self.place = f"{page}:{line}"
        self.line = line
        self.language = language
        self.code = code
        self.directives = directives

    def not_run(self):
        """The reason the block is not run, or None."""
        return next((text for kind, text in self.directives if kind == "not run"), None)

    def source(self):
        """The code with the block's replacements made; each must match."""
        code = self.code
        for kind, text in self.directives:
            if kind == "replace":
                old, new = text
                if old not in code:
                    raise AssertionError(f"{self.place}: `{old} => {new}` matches nothing")
                code = code.replace(old, new)
        return code


def _directive(text, place):
    text = text.strip()
    if text.startswith("not run:"):
        reason = text[len("not run:") :].strip()
        assert reason, f"{place}: `not run:` without a reason"
        return ("not run", reason)
    if re.fullmatch(r"exit -?\d+", text):
        return ("exit", int(text.split()[1]))
    old, sep, new = text.partition(" => ")
    assert sep and old.strip(), f"{place}: `{text}` is not a directive"
    return ("replace", (old.strip(), new.strip()))


def blocks(markdown, page):
    """Every fenced block of a page, with the directives directly above its fence."""
    found, pending = [], []
    lines = markdown.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i].strip()
        if line.startswith("<!-- test:"):
            assert line.endswith("-->"), f"{page}:{i + 1}: a directive ends with `-->`"
            pending.append(_directive(line[len("<!-- test:") : -len("-->")], f"{page}:{i + 1}"))
        elif line.startswith("```"):
            language = (line[3:].split() or [""])[0]
            start, body = i, []
            i += 1
            while i < len(lines) and lines[i].strip() != "```":
                body.append(lines[i])
                i += 1
            assert i < len(lines), f"{page}:{start + 1}: the fence is never closed"
            found.append(Block(page, start + 1, language, "\n".join(body) + "\n", pending))
            pending = []
        else:
            assert not pending, f"{page}:{i}: a directive must stand directly above a fence"
        i += 1
    assert not pending, f"{page}: a directive above no fence"
    return found


def imports_rattle(code):
    """Whether the code imports rattle itself (it starts a session)."""
    tree = ast.parse(code)
    return any(
        (isinstance(node, ast.Import) and any(a.name == "rattle" for a in node.names))
        or (isinstance(node, ast.ImportFrom) and node.module == "rattle")
        for node in ast.walk(tree)
    )


def needed(code):
    """The optional packages the code needs, by import name."""
    names = set()
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.Import):
            names.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module.split(".")[0])
    names.update(package for call, package in NEEDED_BY_CALLS.items() if call in code)
    return sorted(names - PRESENT)


def sessions():
    """The sessions of every page: lists of the python blocks a reader runs together."""
    out = []
    for path in PAGES:
        page = path.relative_to(REPOSITORY).as_posix()
        current = None
        for block in blocks(path.read_text(encoding="utf-8"), page):
            if block.language != "python":
                continue
            code = block.code if block.not_run() else block.source()
            if current is None or (not block.not_run() and imports_rattle(code)):
                current = []
                out.append(current)
            current.append(block)
    return out


SESSIONS = sessions()


def test_the_guide_has_python_sessions():
    places = [s[0].place for s in SESSIONS]
    assert len(SESSIONS) >= 5, places
    assert any(p.startswith("README.md:") for p in places), places
    assert any(p.startswith("crates/python/README.md:") for p in places), places


@pytest.mark.parametrize("session", SESSIONS, ids=[s[0].place for s in SESSIONS])
def test_session_runs(session, tmp_path, monkeypatch):
    run = [b for b in session if not b.not_run()]
    if not run:
        pytest.skip("; ".join(f"{b.place}: not run: {b.not_run()}" for b in session))
    for package in sorted({p for b in run for p in needed(b.source())}):
        pytest.importorskip(package)
        if package == "matplotlib":
            import matplotlib

            matplotlib.use("Agg")  # plt.show() returns at once
    shutil.copytree(SCENES, tmp_path / "data" / "scenes")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__main__"}
    try:
        for block in run:
            # Blank lines before the code keep a traceback's line numbers the page's.
            code = "\n" * block.line + block.source()
            exec(compile(code, block.place.split(":")[0], "exec"), namespace)
    finally:
        _close(namespace)


def _close(namespace):
    """Closes what a session leaves open: a Dask client and cluster, matplotlib's figures."""
    for name in ("client", "cluster"):
        close = getattr(namespace.get(name), "close", None)
        if callable(close):
            close()
    if "matplotlib" in sys.modules:
        import matplotlib.pyplot as plt

        plt.close("all")


# The reader itself, on planted pages: what it must find and refuse.


def test_blocks_are_read_with_their_directives():
    page = (
        "Text.\n\n<!-- test: not run: needs a cluster -->\n```python\n    cluster.scale(2)\n```\n"
        "<!-- test: (0.1, 4.0, 200) => (0.1, 4.0, 5) -->\n```python\nimport rattle\n"
        "f = rattle.frequencies(0.1, 4.0, 200)\n```\n\n```sh\nrattle orbit\n```\n"
    )
    found = blocks(page, "p.md")
    assert [b.language for b in found] == ["python", "python", "sh"]
    assert found[0].not_run() == "needs a cluster"
    assert found[1].place == "p.md:8"
    assert "frequencies(0.1, 4.0, 5)" in found[1].source()
    with pytest.raises(AssertionError, match="matches nothing"):
        Block("p.md", 1, "python", "x = 1\n", [("replace", ("y", "z"))]).source()
    with pytest.raises(AssertionError, match="directly above a fence"):
        blocks("<!-- test: a => b -->\ntext\n```python\nx\n```\n", "p.md")
    with pytest.raises(AssertionError, match="not a directive"):
        blocks("<!-- test: nonsense -->\n```python\nx\n```\n", "p.md")


def test_sessions_and_needs_are_found():
    assert imports_rattle("import rattle\n") and imports_rattle("from rattle import map\n")
    assert not imports_rattle("chain = rattle.Scene.paper()\n")
    code = (
        "import rattle, numpy as np\nimport matplotlib.pyplot as plt\n"
        "from dask.distributed import Client\nimport json\nm.to_pandas()\n"
    )
    assert needed(code) == ["dask", "matplotlib", "pandas"]


def test_a_failing_snippet_fails(tmp_path, monkeypatch):
    """A planted page's snippet with a misspelt function fails as a session's run does."""
    page = "```python\nimport rattle\nrattle.simulte(rattle.Scene.paper(), 2.0)\n```\n"
    (session,) = [[b] for b in blocks(page, "p.md")]
    with pytest.raises(AttributeError, match="simulte"):
        test_session_runs(session, tmp_path, monkeypatch)
    good = [blocks(page.replace("simulte", "simulate"), "p.md")[0]]
    test_session_runs(good, tmp_path / "again", monkeypatch)
