"""What the documents name exists: every dotted ``cof_gym.…`` name in the READMEs (the shipped policies' cards
among them), docs/ and the code's docstrings and comments imports (a module, or an attribute chain of one), and
every repository path they write (``cof_gym/…``, ``experiments/…``, ``tests/…``, ``docs/…``, ``agents/…``) is a
file or a folder of this checkout, and every markdown link to a heading (``[text](docs/x.md#heading)``) finds that
heading. A module split, a rename or a retitled section that leaves a reference behind fails here."""

from __future__ import annotations

import importlib
import re
from functools import lru_cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = [ROOT / "README.md", ROOT / "agents" / "README.md", ROOT / "experiments" / "README.md",
             *sorted((ROOT / "docs").glob("*.md")),
             *sorted((ROOT / "cof_gym" / "agents" / "policies").glob("*/README.md"))]
SOURCES = sorted(p for d in ("cof_gym", "experiments") for p in (ROOT / d).rglob("*.py"))
DOTTED = re.compile(r"(?<![\w/])(cof_gym(?:\.[A-Za-z_]\w*)+)")
PATH = re.compile(r"(?<![\w/.])((?:cof_gym|experiments|tests|docs|agents)/[\w./-]*)")
IMPORT_LINE = re.compile(r"^\s*(from|import) ")
HEADING = re.compile(r"^#+ (.*)$", re.M)
ANCHOR_LINK = re.compile(r"\]\(([^)#\s]*)#([^)\s]+)\)")  # [text](file.md#anchor) or [text](#anchor)


@lru_cache(maxsize=None)
def resolves(name: str) -> bool:
    """Whether ``name`` is a module, or an attribute chain of the longest importable module it starts with."""
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        for attribute in parts[k:]:
            if not hasattr(obj, attribute):
                return False
            obj = getattr(obj, attribute)
        return True
    return False


def dotted_names(path: Path) -> list[tuple[int, str]]:
    """(line, name) of every dotted ``cof_gym`` name outside import statements."""
    return [(k, m.group(1)) for k, line in enumerate(path.read_text().splitlines(), 1)
            if not IMPORT_LINE.match(line) for m in DOTTED.finditer(line)]


@pytest.mark.parametrize("path", DOCUMENTS + SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_dotted_name_resolves(path: Path) -> None:
    missing = [(line, name) for line, name in dotted_names(path) if not resolves(name)]
    assert not missing, f"{path.relative_to(ROOT)}: {missing}"


def missing_paths(path: Path) -> list[str]:
    """The repository paths ``path`` writes that are no file or folder of this checkout (a prefix of a family of
    files, ``member_*`` or ``v2_confirmationN_*``, is written up to its underscore and not checked)."""
    written = {m.group(1).rstrip(".,;:)") for m in PATH.finditer(path.read_text())}
    return sorted(p for p in written if not p.endswith("_") and not (ROOT / p).exists())


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_repository_path_exists(path: Path) -> None:
    missing = missing_paths(path)
    assert not missing, f"{path.relative_to(ROOT)}: {missing}"


def test_the_checks_see_a_stale_reference(tmp_path: Path) -> None:
    stale = tmp_path / "stale.md"
    stale.write_text("`cof_gym.agents.interrogator.RunawayBracket` and `cof_gym.agents.runaway.RunawayBracket`, in\n"
                     "`cof_gym/agents/interrogator.py` (moved) and `cof_gym/agents/runaway.py`\n")
    assert [resolves(name) for _, name in dotted_names(stale)] == [False, True]
    assert missing_paths(stale) == ["cof_gym/agents/interrogator.py"]


def test_every_experiment_script_is_in_the_experiments_readme() -> None:
    listed = (ROOT / "experiments" / "README.md").read_text()
    scripts = sorted(p.name for p in (ROOT / "experiments").iterdir() if p.suffix in (".py", ".sh"))
    assert [s for s in scripts if f"`{s}`" not in listed] == []


def heading_anchor(heading: str) -> str:
    """The anchor GitHub gives a markdown heading: lower case, punctuation but hyphens dropped, spaces as hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def broken_anchors(path: Path) -> list[str]:
    """The ``file#anchor`` links of ``path`` whose file is a markdown document without a heading of that anchor."""
    broken = []
    for target, anchor in ANCHOR_LINK.findall(path.read_text()):
        document = (path.parent / target).resolve() if target else path
        if document.suffix != ".md" or not document.is_file():
            continue  # a missing file is test_every_repository_path_exists's
        if anchor not in {heading_anchor(h) for h in HEADING.findall(document.read_text())}:
            broken.append(f"{target}#{anchor}")
    return broken


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_link_to_a_heading_finds_it(path: Path) -> None:
    broken = broken_anchors(path)
    assert not broken, f"{path.relative_to(ROOT)}: {broken}"


def test_the_anchor_check_sees_a_retitled_heading(tmp_path: Path) -> None:
    (tmp_path / "notes.md").write_text("# Notes\n\n## How the numbers moved (sessions 20-53)\n")
    page = tmp_path / "page.md"
    page.write_text("[a](notes.md#how-the-numbers-moved-sessions-20-53), "
                    "[b](notes.md#how-the-numbers-moved-sessions-20-48), [c](#notes-here)\n\n## Notes here\n")
    assert broken_anchors(page) == ["notes.md#how-the-numbers-moved-sessions-20-48"]


FILE_LINK = re.compile(r"\]\(([^)#\s:]+)(?:#[^)\s]*)?\)")  # [text](relative/path) or (relative/path#anchor)


def broken_file_links(path: Path) -> list[str]:
    """The relative links of ``path`` (not a URL, not an anchor alone) that name no file or folder, read from the
    document's own folder as a markdown viewer reads them."""
    return [target for target in FILE_LINK.findall(path.read_text()) if not (path.parent / target).exists()]


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_finds_its_file(path: Path) -> None:
    """(docs/interrogator.md linked docs/results.md as 'docs/results.md': docs/docs/results.md.)"""
    broken = broken_file_links(path)
    assert not broken, f"{path.relative_to(ROOT)}: {broken}"


def test_the_file_link_check_sees_a_path_from_the_wrong_folder(tmp_path: Path) -> None:
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "results.md").write_text("# Results\n")
    page = tmp_path / "docs" / "page.md"
    page.write_text("[a](results.md), [b](docs/results.md#results), [c](https://example.org/x.md), [d](#here)\n")
    assert broken_file_links(page) == ["docs/results.md"]
