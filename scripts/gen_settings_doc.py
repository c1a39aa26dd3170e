#!/usr/bin/env python3
"""Writes docs/settings.md, the reference of every render setting, from the settings schema.

    .venv-test/bin/python scripts/gen_settings_doc.py            # (re)write docs/settings.md
    .venv-test/bin/python scripts/gen_settings_doc.py --check    # exit 1 if it is out of date

Run it with a Python that has the `photonmap` package installed (scripts/test.sh makes one in
.venv-test). The schema is the core's (`photonmap.settings_schema()`, i.e.
`RenderSettings::schema()` in src/render/settings/mod.rs) and the presets' values are
`photonmap.preset(name)`: the command-line flags, the `photonmap.render` keywords and the
Blender add-on's properties are all built from the same schema, so this page describes the
three at once. Change a setting's documentation, default or range in the core, rebuild the
package, and run this script again; tests/python/test_settings_doc.py fails until then.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "docs" / "settings.md"

#: The Blender add-on's panel of each schema group (blender_addon/ui.py), under Render
#: Properties.
PANELS = {
    "quality": "Quality",
    "photons": "Photons",
    "gathering": "Final Gathering",
    "passes": "Passes",
}

#: Placeholder of a flag's value, by the schema's type.
VALUE_NAMES = {"int": "N", "float": "X", "size": "SIZE", "path": "FILE"}

#: How the schema's types read in prose.
TYPE_NAMES = {
    "int": "integer",
    "float": "number",
    "bool": "on/off",
    "enum": "one of the choices below",
    "size": "byte count: an integer, or a size with a binary suffix (`512M`, `8G`)",
    "path": "file path",
}

UNITS = {"distance": "scene units", "seconds": "seconds"}


def load_schema() -> list[dict[str, Any]]:
    """The settings schema of the installed package."""
    import photonmap

    return photonmap.settings_schema()


def load_presets(names: list[str]) -> dict[str, dict[str, Any]]:
    """Each quality preset's values of the preset fields, by preset name."""
    import photonmap

    return {n: photonmap.preset(n) for n in names}


def _value(v: Any) -> str:
    """A value as Python writes it (the keyword's value), in code format."""
    if v is None:
        return "unset (`None`)"
    return f"`{v!r}`"


def _number(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else repr(x)


def _range(f: dict[str, Any]) -> str | None:
    lo, hi = f["min"], f["max"]
    if lo is not None and hi is not None:
        left = "(" if f["min_open"] else "["
        right = ")" if f["max_open"] else "]"
        text = f"{left}{_number(lo)}, {_number(hi)}{right}"
    elif lo is not None:
        text = f"{'>' if f['min_open'] else '≥'} {_number(lo)}"
    elif hi is not None:
        text = f"{'<' if f['max_open'] else '≤'} {_number(hi)}"
    else:
        text = None
    if f["soft_max"] is not None:
        soft = f"Blender's slider stops at {_number(f['soft_max'])}"
        text = f"{text}; {soft}" if text else soft
    return text


def _flag(f: dict[str, Any]) -> str:
    kind = f["type"]
    if kind == "bool":
        # A switch takes no value; the other booleans take on or off.
        return f"`{f['flag']}` (a switch)" if f["switch"] else f"`{f['flag']} on|off`"
    if kind == "enum":
        return f"`{f['flag']} {'|'.join(c['name'] for c in f['choices'])}`"
    value = "SECONDS" if f["unit"] == "seconds" else VALUE_NAMES.get(kind, "VALUE")
    return f"`{f['flag']} {value}`"


def _blender(f: dict[str, Any]) -> str:
    panel = PANELS.get(f["group"], f["group"])
    return (f"Render Properties → {panel} → *{f['label']}* "
            f"(`scene.photonmap.{f['name']}`)")


def _applies(f: dict[str, Any]) -> str | None:
    parts = []
    if f["modes"]:
        parts.append("in the " + " and ".join(f"`{m}`" for m in f["modes"])
                     + (" modes" if len(f["modes"]) > 1 else " mode") + " only")
    if f["requires"]:
        parts.append(f"only while `{f['requires']}` is on")
    return "; ".join(parts) or None


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n\n", "<br>").replace("\n", " ")


def _section(f: dict[str, Any], default_preset: str) -> list[str]:
    lines = [f"### `{f['name']}`", ""]
    lines += [p.strip() for p in f["doc"].split("\n\n")][:1]
    for para in [p.strip() for p in f["doc"].split("\n\n")][1:]:
        lines += ["", para]
    lines.append("")
    rows = [
        ("command line", _flag(f)),
        ("Python", f"`photonmap.render(scene, {f['name']}=...)`"),
        ("Blender", _blender(f)),
        ("type", TYPE_NAMES.get(f["type"], f["type"])
         + (", optional" if f["optional"] else "")),
    ]
    default = _value(f["default"])
    if f["preset"]:
        default += f" (the `{default_preset}` preset's; the quality preset sets it)"
    rows.append(("default", default))
    rng = _range(f)
    if rng:
        rows.append(("range", rng))
    if f["unit"]:
        rows.append(("unit", UNITS.get(f["unit"], f["unit"])))
    applies = _applies(f)
    if applies:
        rows.append(("applies", applies))
    lines += ["| | |", "|---|---|"]
    lines += [f"| {k} | {_cell(v)} |" for k, v in rows]
    if f["choices"]:
        lines += ["", "| choice | Blender label | meaning |", "|---|---|---|"]
        lines += [f"| `{c['name']}` | {_cell(c['label'])} | {_cell(c['doc'])} |"
                  for c in f["choices"]]
    lines.append("")
    return lines


def render(schema: list[dict[str, Any]], presets: dict[str, dict[str, Any]]) -> str:
    """The text of docs/settings.md for this schema and these presets."""
    quality = next(f for f in schema if f["name"] == "quality")
    default_preset = quality["default"]
    names = list(presets)
    out = [
        "# Render settings",
        "",
        "<!-- Generated by scripts/gen_settings_doc.py from photonmap.settings_schema(); "
        "do not edit. -->",
        "",
        "Every render setting, as the core's settings schema defines it "
        "(`photonmap.settings_schema()`). One definition gives the `photonmap render` flags, "
        "the keywords of `photonmap.render` and the Blender add-on's properties "
        "(`scene.photonmap`, in the Render Properties panels): a keyword is the flag without "
        "its dashes (`--final-gather-rays` is `final_gather_rays=`), and a Blender property "
        "has the keyword's name. A setting not given takes its default; a preset field not "
        "given takes the value of the `quality` preset. In Python `None` means not given; in "
        "Blender an optional number, size or path that no preset fills shows 0 or an empty "
        "field for not given.",
        "",
        "## Presets",
        "",
        "The values each `quality` preset gives its fields (`photonmap.preset(name)`); "
        f"`{default_preset}` is the default. Unset means the setting's own default (see its "
        "section).",
        "",
        "| setting | " + " | ".join(f"`{n}`" for n in names) + " |",
        "|---|" + "---:|" * len(names),
    ]
    for f in schema:
        if f["preset"]:
            vals = [presets[n].get(f["name"]) for n in names]
            cells = ["unset" if v is None else f"`{v!r}`" for v in vals]
            out.append(f"| [`{f['name']}`](#{f['name']}) | " + " | ".join(cells) + " |")
    out += ["", "## All settings", "",
            "| setting | flag | Blender label | Blender panel | default |",
            "|---|---|---|---|---|"]
    for f in schema:
        d = "unset" if f["default"] is None else f"`{f['default']!r}`"
        if f["preset"]:
            d += " (preset)"
        out.append(f"| [`{f['name']}`](#{f['name']}) | `{f['flag']}` | {f['label']} | "
                   f"{PANELS.get(f['group'], f['group'])} | {d} |")
    out.append("")
    groups: list[str] = []
    for f in schema:
        if f["group"] not in groups:
            groups.append(f["group"])
    for g in groups:
        out += [f"## {PANELS.get(g, g)}", ""]
        for f in schema:
            if f["group"] == g:
                out += _section(f, default_preset)
    return "\n".join(out).rstrip("\n") + "\n"


def generate() -> str:
    """The text of docs/settings.md from the installed package's schema and presets."""
    schema = load_schema()
    quality = next(f for f in schema if f["name"] == "quality")
    presets = load_presets([c["name"] for c in quality["choices"]])
    return render(schema, presets)


def difference(path: Path = OUT, text: str | None = None) -> str | None:
    """None when ``path`` holds what the script writes; else the first line that differs."""
    want = generate() if text is None else text
    if not path.exists():
        return f"{path} does not exist"
    have = path.read_text(encoding="utf-8")
    if have == want:
        return None
    a, b = have.splitlines(), want.splitlines()
    for i, (x, y) in enumerate(zip(a, b), start=1):
        if x != y:
            return f"{path}:{i} differs:\n  file:      {x}\n  generated: {y}"
    n = min(len(a), len(b)) + 1
    if len(a) != len(b):
        extra = "file has extra lines" if len(a) > len(b) else "file ends early"
        return f"{path}:{n} differs: {extra}"
    return f"{path}: differs in line endings or the final newline"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true",
                    help="write nothing; exit 1 naming the first differing line if the file "
                         "is not what this script writes")
    ap.add_argument("--out", type=Path, default=OUT, help="the file (default: docs/settings.md)")
    a = ap.parse_args(argv)
    if a.check:
        diff = difference(a.out)
        if diff:
            print(f"{diff}\n{a.out} is out of date: run "
                  "`python scripts/gen_settings_doc.py` with the package installed",
                  file=sys.stderr)
            return 1
        print(f"{a.out} is up to date")
        return 0
    a.out.write_text(generate(), encoding="utf-8")
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
