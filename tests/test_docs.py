"""Every link between the README, ARCHITECTURE.md and docs/ leads somewhere.

A link to a local file (``docs/models.md``, ``images/display.png``, ``../ARCHITECTURE.md``)
must name a file or directory that exists, and a link with an anchor into a local Markdown
file (``reliability.md#saving-files``, ``#fuzzers``) must name one of its headings, as GitHub
makes anchors of headings: the heading's text lowercased, punctuation dropped (``-`` and
``_`` kept), each space a ``-``, and ``-1``, ``-2`` … after a repeated one.
"""

from __future__ import annotations

import re
import unicodedata
from pathlib import Path

import pytest

from tests.conftest import REPO

PAGES = sorted([*REPO.glob("*.md"), *(REPO / "docs").glob("*.md")])

FENCE = re.compile(r"^\s*(```|~~~)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
EXTERNAL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")  # http:, https:, mailto: …


def prose_lines(text: str) -> list[tuple[int, str]]:
    """The lines outside fenced code blocks, with their numbers."""
    lines, fenced = [], False
    for number, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
        elif not fenced:
            lines.append((number, line))
    return lines


def heading_text(markdown: str) -> str:
    """A heading's text as GitHub renders it: code spans' contents, links' texts, no
    emphasis markers or HTML tags."""
    text = CODE_SPAN.sub(lambda m: m.group(2).strip(), markdown)
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = re.sub(r"<[^>]+>", "", text)
    return re.sub(r"\*+", "", text)


def slug(text: str) -> str:
    """GitHub's anchor of a heading's text (github-slugger): lowercase, everything but
    letters, digits, marks, ``-``, ``_`` and spaces dropped, spaces to ``-``."""
    kept = "".join(c for c in text.lower() if c in "-_ " or unicodedata.category(c)[0] in "LNM")
    return kept.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    found: set[str] = set()
    seen: dict[str, int] = {}
    for _, line in prose_lines(path.read_text(encoding="utf-8")):
        match = HEADING.match(line)
        if match:
            base = slug(heading_text(match.group(2)))
            count = seen.get(base, 0)
            seen[base] = count + 1
            found.add(base if count == 0 else f"{base}-{count}")
    return found


def links(path: Path) -> list[tuple[int, str]]:
    """Every link target in ``path``'s prose (inline, image and reference links)."""
    found = []
    for number, line in prose_lines(path.read_text(encoding="utf-8")):
        plain = CODE_SPAN.sub("", line)
        found += [(number, m.group(1)) for m in INLINE_LINK.finditer(plain)]
        reference = REFERENCE.match(plain)
        if reference:
            found.append((number, reference.group(1)))
    return found


def broken(path: Path, root: Path = REPO) -> list[str]:
    """What is wrong with ``path``'s local links, one line each (``root``: where paths in
    the messages start)."""
    wrong = []
    for number, target in links(path):
        if EXTERNAL.match(target):
            continue
        file, _, anchor = target.partition("#")
        goal = (path.parent / file).resolve() if file else path
        where = f"{path.relative_to(root)}:{number}: {target}"
        if not goal.exists():
            wrong.append(f"{where}: no such file")
        elif anchor and goal.suffix == ".md" and anchor not in anchors(goal):
            wrong.append(f"{where}: no heading makes #{anchor}")
    return wrong


def test_the_pages_are_found() -> None:
    names = {p.relative_to(REPO).as_posix() for p in PAGES}
    assert {"README.md", "ARCHITECTURE.md", "docs/tutorial.md"} <= names


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(REPO).as_posix())
def test_every_link_resolves(page: Path) -> None:
    wrong = broken(page)
    assert not wrong, "\n".join(wrong)


def test_the_readme_leads_to_every_page() -> None:
    """The README is the entrance: every page of docs/ and ARCHITECTURE.md is one click away."""
    readme = REPO / "README.md"
    linked = {(REPO / t.partition("#")[0]).resolve() for _, t in links(readme)}
    missing = [p.relative_to(REPO).as_posix() for p in PAGES if p != readme and p not in linked]
    assert not missing, missing


@pytest.mark.parametrize(
    ("heading", "anchor"),
    [
        ("Install", "install"),
        (
            "`belvedere bag` — rosbag record, play, info, reindex",
            "belvedere-bag--rosbag-record-play-info-reindex",
        ),
        (
            "Foxglove: `--foxglove [PORT]`, `belvedere foxglove`",
            "foxglove---foxglove-port-belvedere-foxglove",
        ),
        (
            "Maps: `map_server`, `map_saver`, `belvedere map show`",
            "maps-map_server-map_saver-belvedere-map-show",
        ),
        ("Where a new ROS package's node goes", "where-a-new-ros-packages-node-goes"),
        ("Python ≥ 3.11 and **bold** [link](x.md)", "python--311-and-bold-link"),
        ("\u00c9lan 2.0 \u00d7 3", "\u00e9lan-20--3"),
    ],
)
def test_anchors_are_githubs(heading: str, anchor: str) -> None:
    assert slug(heading_text(heading)) == anchor


def test_a_broken_link_is_found(tmp_path: Path) -> None:
    (tmp_path / "a.md").write_text("# Title\n\n## Twice\n\n## Twice\n", encoding="utf-8")
    page = tmp_path / "b.md"
    page.write_text(
        "[ok](a.md#title) [ok](a.md#twice-1) [ok](#here) ![ok](a.md) <https://x.y> [ok](.)\n"
        "[no](a.md#twice-2) [no](c.md) [no](#there) `[code](c.md)` [ok](https://x.y/c.md)\n"
        "```\n[fenced](c.md)\n```\n"
        "## Here\n",
        encoding="utf-8",
    )
    assert broken(page, root=tmp_path) == [
        "b.md:2: a.md#twice-2: no heading makes #twice-2",
        "b.md:2: c.md: no such file",
        "b.md:2: #there: no heading makes #there",
    ]
