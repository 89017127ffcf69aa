"""Issue 47, item 9: a link check of the README and the docs. Every relative link's file
exists, every ``#anchor`` is a heading of its page (the slug MkDocs and GitHub give it), and
every page that sends the reader to a README section by name ("the README's section "X"")
names a heading the README has. External links are not fetched (no network in CI)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = [ROOT / "README.md", *sorted(p for p in DOCS.rglob("*.md") if "site" not in p.parts)]

#: [text](target) outside code: the target up to a space or the closing parenthesis
LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)|!\[[^\]]*\]\(([^)\s]+)\)")
#: a README section named in prose: README's section "X" / README section "X"
README_SECTION = re.compile(r"README(?:'s)?\s+section\s+\"([^\"]+)\"", re.S)


def _prose(text: str) -> str:
    """The page without its fenced code blocks and inline code."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.M | re.S)
    return re.sub(r"`[^`\n]*`", "", text)


def slug(heading: str) -> str:
    """A heading's anchor as Python-Markdown's toc (MkDocs) and GitHub make it: lower case,
    punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return re.sub(r"\s+", "-", text)


def anchors(page: Path) -> set[str]:
    """The anchors of a Markdown page's headings."""
    text = re.sub(r"^```.*?^```", "", page.read_text(encoding="utf-8"), flags=re.M | re.S)
    headings = re.findall(r"^#{1,6}\s+(.*?)\s*#*\s*$", text, re.M)
    return {slug(h) for h in headings}


def _links(page: Path) -> list[str]:
    return [a or b for a, b in LINK.findall(_prose(page.read_text(encoding="utf-8")))]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_resolves(page):
    broken = []
    for target in _links(page):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto: ...
            continue
        path, _, anchor = target.partition("#")
        file = page if not path else (page.parent / path).resolve()
        if not file.exists():
            broken.append(f"{target}: no such file")
            continue
        if anchor and file.suffix == ".md" and anchor not in anchors(file):
            broken.append(f"{target}: no heading #{anchor} in {file.name}")
    assert not broken, f"{page.relative_to(ROOT)}: " + "; ".join(broken)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_readme_section_named_exists(page):
    readme = anchors(ROOT / "README.md")
    named = README_SECTION.findall(page.read_text(encoding="utf-8"))
    missing = [n for n in named if slug(" ".join(n.split())) not in readme]
    assert not missing, f"{page.relative_to(ROOT)} names README sections {missing}"


def test_the_checker_finds_a_broken_link_and_a_missing_section(tmp_path):
    """The check itself: a missing file, a missing anchor and a README section that is not
    there are each found."""
    page = tmp_path / "page.md"
    page.write_text(
        "# Title\n[a](nowhere.md) [b](#title) [c](#absent)\n"
        'The README\'s section "Gymnasium environment" says so.\n',
        encoding="utf-8",
    )
    assert _links(page) == ["nowhere.md", "#title", "#absent"]
    assert anchors(page) == {"title"}
    assert README_SECTION.findall(page.read_text()) == ["Gymnasium environment"]
    assert slug("The one command and its claim") in anchors(ROOT / "README.md")
