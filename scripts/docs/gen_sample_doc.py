"""Regenerate the generated parts of docs/sample.md from sandlight.sample, so they cannot drift.

The parameter table comes from ``PARAMETERS``, the preset list from the headers of the preset
files. Each part sits between ``<!-- BEGIN name -->`` and ``<!-- END name -->`` markers; the
text outside the markers is left alone.

Usage: ``python3 scripts/docs/gen_sample_doc.py`` (rewrite) or ``... --check`` (exit 1 if stale).
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
from importlib import resources
from pathlib import Path

from sandlight.sample import PARAMETERS, Parameter, SandSample

DOC = Path(__file__).resolve().parents[2] / "docs" / "sample.md"


def _domain(p: Parameter) -> str:
    if p.kind == "choice":
        return ", ".join(f"`{c}`" for c in p.choices)
    left = "(" if p.low_open else "["
    return f"{left}{p.low:g}, {p.high:g}]"


def _default(p: Parameter) -> str:
    return f"`{p.default}`" if p.kind == "choice" else f"{p.default:g}"


def parameter_table() -> str:
    """The Markdown table of every parameter (name, meaning, unit, default, domain)."""
    rows = ["| name | meaning | unit | default | domain |", "|---|---|---|---|---|"]
    for p in PARAMETERS:
        added = " *(sandlight addition)*" if p.added else ""
        rows.append(f"| `{p.name}` | {p.description}{added} | {p.unit or '–'} | {_default(p)} | {_domain(p)} |")
    return "\n".join(rows)


def preset_list() -> str:
    """One bullet per preset: its name and the first sentence of its file's header."""
    directory = resources.files("sandlight") / "data" / "presets"
    items = []
    for name in SandSample.presets():
        text = (directory / f"{name}.toml").read_text(encoding="utf-8")
        header = []
        for line in text.splitlines():
            if not line.startswith("#") or line.strip() == "#":
                break
            header.append(line.lstrip("# ").strip())
        summary = " ".join(header).removeprefix(f"{name}:").strip()
        items.append(f"- `{name}`: {summary}")
    return "\n".join(items)


SECTIONS = {"parameter-table": parameter_table, "preset-list": preset_list}


def render(text: str) -> str:
    """`text` with every generated section replaced by its current content."""
    for name, make in SECTIONS.items():
        pattern = re.compile(rf"(<!-- BEGIN {name} -->\n).*?(\n<!-- END {name} -->)", re.S)
        if not pattern.search(text):
            raise SystemExit(f"{DOC}: markers for {name!r} not found")
        text = pattern.sub(lambda m, make=make: m.group(1) + make() + m.group(2), text)
    return text


def main(argv: list[str]) -> int:
    current = DOC.read_text(encoding="utf-8")
    fresh = render(current)
    if "--check" in argv:
        if fresh != current:
            print(f"{DOC} is out of date: run python3 scripts/docs/gen_sample_doc.py", file=sys.stderr)
            return 1
        return 0
    if fresh != current:
        # write to a temporary file next to the target, then rename: never a half-written doc
        fd, tmp = tempfile.mkstemp(dir=DOC.parent, prefix=".sample.md.")
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(fresh)
        os.replace(tmp, DOC)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
