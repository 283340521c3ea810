"""The book's MyST Markdown as plain Jupyter Markdown, for the notebooks the book publishes.

Standard library only. A chapter is written in MyST (targets ``(label)=``, roles such as
``{numref}`` and ``{term}``, directives such as admonitions and dropdowns); JupyterLab,
Notebook 7 and Colab render CommonMark with HTML and math, and would show MyST as text.
:func:`to_jupyter` rewrites one markdown cell:

* targets ``(label)=`` are dropped (the headings keep their own anchors);
* cross-references (``{numref}``, ``{ref}``, ``{doc}``, ``{term}``, ``{eq}``,
  ``{download}``) become links to the hosted book, with the text the book shows ("Fig. 3",
  the section's title), through a :class:`Resolver` the book build supplies; a reference
  it cannot resolve becomes its text;
* ``{math}`` becomes ``$...$``; ``{glue:text}``/``{glue}`` the value the notebook glued,
  when known; ``{sub}``/``{sup}`` HTML; any other role its text;
* admonitions (and ``note``, ``tip``, ``warning`` ...) become block quotes with a bold
  title, dropdowns ``<details>`` with a ``<summary>``, ``{glue:figure}`` the figure's
  number and caption (the figure itself is the output of the cell that made it),
  ``{figure}`` an image with its caption, ``{glossary}`` a list of terms; ``:class:`` and
  other options are dropped; any other directive keeps its body.

Code (fenced blocks and inline spans) is never changed. :func:`myst_left` finds what a
converted text still has of MyST (the tests fail on any).
"""

from __future__ import annotations

import html
import re
from collections.abc import Callable
from dataclasses import dataclass

#: A resolved reference: the text to show and the URL to link (None: plain text).
Link = tuple[str, str | None]
#: ``resolve(role, target, text)``: ``text`` is the reference's own text or None.
Resolve = Callable[[str, str, str | None], Link | None]

ROLE = re.compile(r"\{(?P<role>[A-Za-z][\w:.-]*)\}`(?P<body>[^`]+)`")
TARGET = re.compile(r"^\s*\((?P<label>[^()\s]+)\)=\s*$")
DIRECTIVE = re.compile(r"^(?P<indent>[ ]{0,3})(?P<fence>`{3,}|:{3,})\{(?P<name>[\w:.-]+)\}"
                       r"[ \t]*(?P<arg>.*?)\s*$")
FENCE = re.compile(r"^(?P<indent>[ ]{0,3})(?P<fence>`{3,}|~{3,})(?P<info>[^`]*)$")
#: A role, or an inline code span (kept as it is).
_INLINE = re.compile(r"\{(?P<role>[A-Za-z][\w:.-]*)\}`(?P<body>[^`]+)`"
                     r"|(?P<code>(?P<ticks>`+).+?(?P=ticks))")
OPTION = re.compile(r"^:(?P<key>[\w-]+):[ \t]*(?P<value>.*)$")
#: The admonitions of docutils and sphinx, with the title each shows.
ADMONITIONS = {"admonition": "", "note": "Note", "tip": "Tip", "hint": "Hint",
               "important": "Important", "warning": "Warning", "caution": "Caution",
               "attention": "Attention", "danger": "Danger", "error": "Error",
               "seealso": "See also", "versionadded": "New", "versionchanged": "Changed",
               "deprecated": "Deprecated"}
#: Directives whose content is code: a plain fenced block.
CODE_DIRECTIVES = ("code-block", "code", "sourcecode", "literalinclude")
#: Directives that show nothing in a notebook.
DROPPED = ("toctree", "tableofcontents", "contents", "bibliography", "index", "only")
#: What :func:`myst_left` looks for.
LEFTOVERS = {
    "role": re.compile(r"\{[A-Za-z][\w:.-]*\}`"),
    "directive": re.compile(r"(?m)^[ ]{0,3}(?:`{3,}|:{3,})\{[\w:.-]+\}"),
    "target": re.compile(r"(?m)^\s*\([^()\s]+\)=\s*$"),
    "option": re.compile(r"(?m)^:(?:class|name|alt|open|label|width|align|figwidth|tags):"),
}


@dataclass
class Glue:
    """Values glued by a notebook (``myst_nb.glue``): name -> plain text."""

    text: dict[str, str]


def to_jupyter(text: str, resolve: Resolve, glue: Glue | None = None) -> str:
    """One markdown cell's MyST source as Jupyter Markdown (module docstring)."""
    return "\n".join(_blocks(text.split("\n"), resolve, glue or Glue({})))


def myst_left(text: str) -> list[str]:
    """What MyST ``text`` still has outside code: ``["role: {numref}`...", ...]``."""
    found = []
    for line in _prose_lines(text.split("\n")):
        prose = _INLINE.sub(lambda m: "" if m.group("code") else m.group(0), line)
        for kind, rx in LEFTOVERS.items():
            if rx.search(prose if kind == "role" else line):
                found.append(f"{kind}: {line.strip()[:120]}")
    return found


def _prose_lines(lines: list[str]) -> list[str]:
    """The lines outside fenced code blocks (the fences of directives are prose)."""
    out, fence = [], None
    for line in (re.sub(r"^(?:\s{0,3}>\s?)+", "", ln) for ln in lines):
        if fence is not None:
            if _closes(line, fence):
                fence = None
            continue
        m = FENCE.match(line)
        if m and not DIRECTIVE.match(line):
            fence = m.group("fence")
            continue
        out.append(line)
    return out


def _closes(line: str, fence: str) -> bool:
    s = line.strip()
    return len(s) >= len(fence) and set(s) == {fence[0]}


def _blocks(lines: list[str], resolve: Resolve, glue: Glue) -> list[str]:
    """Convert a list of lines: directives and targets by line, roles in prose."""
    out: list[str] = []
    i = 0
    while i < len(lines):
        line = lines[i]
        d = DIRECTIVE.match(line)
        f = FENCE.match(line)
        if d:
            end = _block_end(lines, i, d.group("fence"))
            body = lines[i + 1:end]
            out += _directive(d.group("name"), d.group("arg"), body, resolve, glue)
            i = end + 1
        elif f:  # code: copied as it is
            end = _block_end(lines, i, f.group("fence"))
            out += lines[i:end + 1]
            i = end + 1
        elif TARGET.match(line):
            i += 1
        else:
            out.append(_roles(line, resolve, glue))
            i += 1
    return out


def _block_end(lines: list[str], start: int, fence: str) -> int:
    """The index of the line that closes the block opened at ``start`` (or past the last).

    As CommonMark and MyST have it: a line of the fence's character alone, at least as long
    as the opening fence (a nested block uses a longer fence outside).
    """
    for j in range(start + 1, len(lines)):
        if _closes(lines[j], fence):
            return j
    return len(lines)


def _options(body: list[str]) -> tuple[dict[str, str], list[str]]:
    """A directive's options (``:key: value`` lines or a ``---`` YAML block) and its content."""
    opts: dict[str, str] = {}
    if body and body[0].strip() == "---":
        end = next((k for k in range(1, len(body)) if body[k].strip() == "---"), 0)
        for ln in body[1:end]:
            key, _, value = ln.partition(":")
            opts[key.strip()] = value.strip()
        return opts, body[end + 1:]
    k = 0
    while k < len(body) and OPTION.match(body[k]):
        m = OPTION.match(body[k])
        assert m is not None
        opts[m.group("key")] = m.group("value")
        k += 1
    while k < len(body) and not body[k].strip():
        k += 1
    return opts, body[k:]


def _directive(name: str, arg: str, body: list[str], resolve: Resolve,
               glue: Glue) -> list[str]:
    opts, content = _options(body)
    inner = _blocks(content, resolve, glue)
    title = _roles(arg, resolve, glue)
    if name in ADMONITIONS:
        head = title or ADMONITIONS[name]
        quoted = [f"> {ln}" if ln.strip() else ">" for ln in inner]
        return ([f"> **{head}**", ">"] if head else []) + quoted + [""]
    if name == "dropdown":
        return ["<details>", f"<summary>{_summary(title)}</summary>", "", *inner, "",
                "</details>", ""]
    if name in ("glue:figure", "glue:any", "glue"):
        return _caption(opts.get("name", ""), inner, resolve, "the output of the cell above")
    if name == "figure":
        alt = opts.get("alt", "")
        url = _link_of(resolve("figure-file", arg, None))
        return [f"![{alt}]({url or arg})", "", *_caption(opts.get("name", ""), inner, resolve,
                                                         "")]
    if name == "glossary":
        return _glossary(content, resolve, glue)
    if name in CODE_DIRECTIVES:
        return [f"```{arg}", *content, "```"]
    if name in ("math",):
        return ["$$", *content, "$$"]
    if name in DROPPED:
        return []
    return inner + [""]


def _summary(title: str) -> str:
    """A dropdown's title for ``<summary>`` (HTML: code spans as ``<code>``, math kept)."""
    parts = re.split(r"(`[^`]+`)", title)
    return "".join(f"<code>{html.escape(p[1:-1])}</code>" if p.startswith("`") and
                   p.endswith("`") and len(p) > 1 else p for p in parts)


def _caption(label: str, caption: list[str], resolve: Resolve, where: str) -> list[str]:
    number = resolve("numref", label, None) if label else None
    head = f"**{number[0]}.** " if number else ""
    text = " ".join(ln.strip() for ln in caption if ln.strip())
    if where:
        text = f"{text} ({where})" if text else f"({where})"
    return [head + text, ""]


def _glossary(content: list[str], resolve: Resolve, glue: Glue) -> list[str]:
    out: list[str] = []
    for ln in content:
        if ln.strip() and not ln.startswith((" ", "\t")):
            out.append(f"* **{_roles(ln.strip(), resolve, glue)}**:")
        elif ln.strip() and out:
            out[-1] += " " + _roles(ln.strip(), resolve, glue)
    return out + [""]


def _link_of(found: Link | None) -> str | None:
    return found[1] if found else None


def _split_target(body: str) -> tuple[str | None, str]:
    """``text <target>`` -> (text, target); ``target`` -> (None, target)."""
    m = re.match(r"^(?P<text>.*?)\s*<(?P<target>[^<>]+)>$", body.strip(), re.S)
    if m and m.group("text"):
        return m.group("text"), m.group("target").strip()
    return None, body.strip().lstrip("~!")


def _roles(line: str, resolve: Resolve, glue: Glue) -> str:
    """The roles of one line of prose converted; inline code spans kept as they are."""
    def sub(m: re.Match[str]) -> str:
        if m.group("code"):
            return m.group("code")
        return _role(m.group("role"), m.group("body"), resolve, glue)

    return _INLINE.sub(sub, line)


def _role(role: str, body: str, resolve: Resolve, glue: Glue) -> str:
    if role == "math":
        return f"${body}$"
    if role in ("sub", "sup"):
        return f"<{role}>{html.escape(body)}</{role}>"
    if role == "abbr":
        return re.sub(r"\s*\(.*\)\s*$", "", body)
    if role.startswith("glue"):
        name = body.split(":", 1)[0].strip()
        return glue.text.get(name, name)
    text, target = _split_target(body)
    found = resolve(role, target, text)
    if found is None:
        return text or target
    shown, url = found
    shown = shown.replace("%s", "").strip() if shown else (text or target)
    return f"[{shown}]({url})" if url else shown
