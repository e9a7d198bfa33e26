"""The Markdown the harness writes (``bench.md``, ``hard.md``, ``importer.md``, ``errata.md``) as HTML: headings
(with a code host's anchors, :func:`slug`), paragraphs, bullet lists, pipe tables, fenced code, inline code,
emphasis and links/images. Enough for our own files; not a general Markdown implementation (no such library is
among the pinned dependencies)."""

from __future__ import annotations

import html
import re

_INLINE = [
    (re.compile(r"!\[([^\]]*)\]\(([^)\s]+)\)"), r'<img class="figure" alt="\1" src="\2">'),
    (re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)"), r'<a href="\2">\1</a>'),
    (re.compile(r"\*\*([^*]+)\*\*"), r"<b>\1</b>"),
    (re.compile(r"(?<![\w*])\*([^*\s][^*]*)\*(?!\w)"), r"<i>\1</i>"),
]


def _inline(text: str, local=lambda target: True) -> str:
    parts = re.split(r"(`[^`]*`)", text)
    out = []
    for part in parts:
        if part.startswith("`") and part.endswith("`") and len(part) > 1:
            out.append(f"<code>{html.escape(part[1:-1])}</code>")
            continue
        piece = html.escape(part, quote=False)
        for pattern, repl in _INLINE:
            if pattern.groups == 2:  # a link or an image: its target must be inside the report
                piece = pattern.sub(lambda m, r=repl: _link(m, r, local), piece)
            else:
                piece = pattern.sub(repl, piece)
        out.append(piece)
    return "".join(out)


def _link(match, repl: str, local) -> str:
    target = match.group(2)
    if not target.startswith("#") and not local(target):  # a link the report folder cannot serve: the text only
        return match.group(1)
    return match.expand(repl.replace(r"\2", html.escape(target)))


def slug(heading: str) -> str:
    """The anchor of a heading as a code host makes it (lower case; letters, digits, ``_``, ``-`` and spaces kept,
    spaces as ``-``): ``[text](#slug)`` links to it here and there."""
    return re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-")


def _cells(line: str) -> list[str]:
    line = line.strip().strip("|")
    return [c.strip() for c in re.split(r"(?<!\\)\|", line)]


def markdown_html(text: str, local=lambda target: True) -> str:
    """HTML for ``text``; ``local(target)`` says whether a link/image target exists in the report folder."""
    lines = text.splitlines()
    out, k = [], 0
    while k < len(lines):
        line = lines[k]
        if line.startswith("```"):
            end = k + 1
            while end < len(lines) and not lines[end].startswith("```"):
                end += 1
            out.append("<pre>" + html.escape("\n".join(lines[k + 1:end])) + "</pre>")
            k = end + 1
            continue
        heading = re.match(r"(#{1,6})\s+(.*)", line)
        if heading:
            level = min(len(heading.group(1)) + 1, 6)  # the page has its own <h1>
            out.append(f'<h{level} id="{slug(heading.group(2))}">{_inline(heading.group(2), local)}</h{level}>')
            k += 1
            continue
        if line.lstrip().startswith("|") and k + 1 < len(lines) and re.match(r"\s*\|?\s*:?-{3,}", lines[k + 1]):
            head = _cells(line)
            rows = []
            k += 2
            while k < len(lines) and lines[k].lstrip().startswith("|"):
                rows.append(_cells(lines[k]))
                k += 1
            body = "".join("<tr>" + "".join(f"<td>{_inline(c, local)}</td>" for c in r) + "</tr>" for r in rows)
            out.append('<div class="wide"><table><tr>' + "".join(f"<th>{_inline(c, local)}</th>" for c in head)
                       + f"</tr>{body}</table></div>")
            continue
        if re.match(r"\s*[-*]\s+", line):
            items = []
            while k < len(lines) and (re.match(r"\s*[-*]\s+", lines[k]) or (lines[k].startswith("  ") and items)):
                if re.match(r"\s*[-*]\s+", lines[k]):
                    items.append(re.sub(r"^\s*[-*]\s+", "", lines[k]))
                else:
                    items[-1] += " " + lines[k].strip()
                k += 1
            out.append("<ul>" + "".join(f"<li>{_inline(i, local)}</li>" for i in items) + "</ul>")
            continue
        if not line.strip():
            k += 1
            continue
        para = []
        while k < len(lines) and lines[k].strip() and not re.match(r"(#{1,6}\s|```|\s*\||\s*[-*]\s+)", lines[k]):
            para.append(lines[k].strip())
            k += 1
        out.append(f"<p>{_inline(' '.join(para), local)}</p>")
    return "\n".join(out)
