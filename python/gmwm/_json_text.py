"""Exact pieces of the library's JSON text.

The library renders every document with report::dump_json (nlohmann's pretty printer,
2-space indent, a trailing newline). A string never holds a raw newline (it is escaped),
so each member of a container starts on a line of its own at the container's indent + 2,
and a nested container closes on a line at that same indent. A member's text is therefore
its lines with that indent removed: exactly what dump_json renders for the member alone.
"""
from __future__ import annotations

import json

_DECODER = json.JSONDecoder()


def _members(text: str) -> list[tuple[str | None, str]]:
    """The members of the top-level object or array of `text` as (key, text) pairs, in
    order (key None for an array's items); each text as dump_json renders it alone."""
    lines = text.split("\n")
    while lines and lines[-1] == "":
        lines.pop()
    if len(lines) < 2 or lines[0] not in ("{", "[") or lines[-1] not in ("}", "]"):
        return []  # an empty container ({} or []) or a scalar: no members
    out: list[tuple[str | None, str]] = []
    i, end = 1, len(lines) - 1
    while i < end:
        line = lines[i]
        if not line.startswith("  ") or line.startswith("   "):
            raise ValueError(f"not the library's JSON layout at line {i + 1}: {line[:60]!r}")
        key: str | None = None
        value = line[2:]
        if lines[0] == "{":
            key, at = _DECODER.raw_decode(value)
            if not value.startswith(": ", at):
                raise ValueError(f"not the library's JSON layout at line {i + 1}: {line[:60]!r}")
            value = value[at + 2:]
        if value in ("{", "["):
            closing = "}" if value == "{" else "]"
            j = i + 1
            while j < end and not (lines[j].startswith("  " + closing) and not lines[j].startswith("   ")):
                j += 1
            body = [lines[k][2:] for k in range(i + 1, j)]
            out.append((key, "\n".join([value, *body, closing]) + "\n"))
            i = j + 1
        else:
            out.append((key, value.removesuffix(",") + "\n"))
            i += 1
    return out


def member_text(text: str, key: str) -> str:
    """The text of the top-level object's member `key`."""
    for k, value in _members(text):
        if k == key:
            return value
    raise KeyError(key)


def item_texts(text: str) -> list[str]:
    """The texts of the top-level array's items."""
    return [value for _, value in _members(text)]
