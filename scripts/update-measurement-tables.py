#!/usr/bin/python3
"""Renders the headline tables of README.md and docs/measurements.md from checked-in data.

Each table lives in tests/data/measurements/NAME.csv: comment lines first (the first names the
command or run the figures came from, its date and machine), then a header row, then one row a
line. A doc holds the rendered table between "<!-- table: NAME -->" and "<!-- end table -->";
docs/measurements.md's contents list sits between "<!-- contents -->" and "<!-- end contents -->"
and is made from its headings.

  scripts/update-measurement-tables.py            rewrite the docs from the data
  scripts/update-measurement-tables.py --check    exit 1 if a doc differs from what the data give,
                                                  or a link's #anchor names no heading

Bad data (a missing or malformed file, a row of the wrong width, an unknown table): exit 2,
naming the file and line. Standard library only.
"""

import argparse
import csv
import difflib
import io
import os
import re
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
DOCS = ["README.md", "docs/measurements.md"]
CONTENTS_DOC = "docs/measurements.md"

TABLE_BEGIN = re.compile(r"^<!-- table: ([a-z0-9-]+) -->$")
TABLE_END = "<!-- end table -->"
CONTENTS_BEGIN = "<!-- contents -->"
CONTENTS_END = "<!-- end contents -->"


class BadInput(Exception):
    """A data file or a doc's markers that cannot be read: exit 2."""


def read_table(path):
    """The header and rows of one table file; BadInput names the file and line."""
    if not os.path.isfile(path):
        raise BadInput(f"{path}: no such table file")
    with open(path, encoding="utf-8", newline="") as f:
        lines = f.read().split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    if not lines or not lines[0].startswith("# ") or len(lines[0].strip()) < 3:
        raise BadInput(f"{path}:1: the first line must be a comment naming the figures' source")
    body = [(n + 1, line) for n, line in enumerate(lines)]
    while body and body[0][1].startswith("#"):
        body.pop(0)
    body = [(n, line) for n, line in body if line.strip()]
    if not body:
        raise BadInput(f"{path}: no header row after the comments")
    header, rows = None, []
    for number, line in body:
        if line.startswith("#"):
            raise BadInput(f"{path}:{number}: a comment line after the header")
        cells = next(csv.reader(io.StringIO(line)))
        for cell in cells:
            if "|" in cell.replace("\\|", "") or "\n" in cell:
                raise BadInput(f"{path}:{number}: a cell holds an unescaped '|': {cell!r}")
        if header is None:
            if any(not c.strip() for c in cells):
                raise BadInput(f"{path}:{number}: an empty column name in the header")
            header = cells
            continue
        if len(cells) != len(header):
            raise BadInput(
                f"{path}:{number}: {len(cells)} cell{'' if len(cells) == 1 else 's'}, "
                f"the header has {len(header)}: {line!r}")
        rows.append(cells)
    if not rows:
        raise BadInput(f"{path}: a header and no rows")
    return header, rows


def render_table(header, rows):
    def line(cells):
        return "|" + "|".join(f" {c.strip()} " if c.strip() else " " for c in cells) + "|"

    return [line(header), "|" + "|".join("---" for _ in header) + "|"] + [line(r) for r in rows]


def slug(heading):
    """GitHub's anchor for a heading: its text lower-cased, punctuation dropped, spaces to '-'."""
    text = re.sub(r"`([^`]*)`", r"\1", heading)
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = text.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def headings(lines):
    """(level, text, anchor) of every heading outside fenced code, anchors made unique as GitHub does."""
    seen, out, fenced = {}, [], False
    for line in lines:
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        m = re.match(r"^(#{1,6}) (.+?)\s*#*\s*$", line)
        if fenced or not m:
            continue
        base = slug(m.group(2))
        count = seen.get(base, 0)
        seen[base] = count + 1
        out.append((len(m.group(1)), m.group(2), base if count == 0 else f"{base}-{count}"))
    return out


def render_contents(lines):
    """One line a study (## heading): its link, then its sections' (### headings) links."""
    out = []
    for level, text, anchor in headings(lines):
        if level == 2:
            out.append(f"- **[{text}](#{anchor})**")
        elif level == 3 and out:
            out[-1] += (": " if out[-1].endswith("**") else " · ") + f"[{text}](#{anchor})"
    return out


def render_doc(path, lines, data_dir, with_contents):
    """The doc with every marked table (and the contents list) rendered from the data."""
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        m = TABLE_BEGIN.match(line)
        if m or (with_contents and line == CONTENTS_BEGIN):
            end = TABLE_END if m else CONTENTS_END
            try:
                j = lines.index(end, i + 1)
            except ValueError:
                raise BadInput(f"{path}:{i + 1}: '{line}' has no '{end}' after it")
            if m:
                header, rows = read_table(os.path.join(data_dir, m.group(1) + ".csv"))
                inner = render_table(header, rows)
            else:
                inner = None  # filled in below, from the rendered doc's headings
            out.append(line)
            out.append(inner)
            out.append(end)
            i = j + 1
            continue
        if line == TABLE_END or line == CONTENTS_END:
            raise BadInput(f"{path}:{i + 1}: '{line}' without its opening marker")
        out.append(line)
        i += 1
    flat = [x for x in out if isinstance(x, str)]
    result = []
    for x in out:
        if x is None:
            result.extend(render_contents(flat))
        elif isinstance(x, list):
            result.extend(x)
        else:
            result.append(x)
    return result


def check_anchors(root, docs):
    """Links of the docs to '#anchor' or 'file.md#anchor' whose anchor names no heading."""
    broken, cache = [], {}
    for doc in docs:
        path = os.path.join(root, doc)
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        for number, line in enumerate(lines, 1):
            for target, anchor in re.findall(r"\]\(([^)#\s]*)#([^)\s]+)\)", line):
                if target and (re.match(r"^[a-z]+:", target) or not target.endswith(".md")):
                    continue
                file = os.path.normpath(os.path.join(os.path.dirname(path), target)) if target else path
                if file not in cache:
                    if not os.path.isfile(file):
                        broken.append(f"{doc}:{number}: link to {target}#{anchor}: no such file")
                        continue
                    with open(file, encoding="utf-8") as f:
                        cache[file] = {a for _, _, a in headings(f.read().split("\n"))}
                if anchor not in cache[file]:
                    broken.append(f"{doc}:{number}: link to {target or doc}#{anchor}: no such heading")
    return broken


SOURCE_SUFFIXES = (".md", ".cpp", ".hpp", ".toml", ".sh", ".py", ".cmake", ".txt", "Makefile", "run")
QUOTED_SECTION = re.compile(r'measurements\.md[`)\]]*[,:]?\s*(?:(?:#|//)\s*)?"([^"]+)"')


def check_quoted_sections(root):
    """Mentions of docs/measurements.md followed by a quoted section name ('docs/measurements.md,
    "Mass scaling"') across the repository's sources whose name starts no heading or bold lead of
    the doc: a renamed section leaves them pointing nowhere."""
    with open(os.path.join(root, CONTENTS_DOC), encoding="utf-8") as f:
        text = f.read()
    leads = [t for _, t, _ in headings(text.split("\n"))] + re.findall(r"\*\*([^*]+)\*\*", text)
    broken = []
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if not d.startswith((".", "build")) and
                   os.path.join(folder, d) != os.path.join(root, "tests", "data", "measurements")]
        for name in files:
            if not name.endswith(SOURCE_SUFFIXES):
                continue
            path = os.path.join(folder, name)
            if os.path.samefile(path, __file__):
                continue
            try:
                with open(path, encoding="utf-8") as f:
                    source = f.read()
            except (UnicodeDecodeError, OSError):
                continue
            for m in QUOTED_SECTION.finditer(source):
                quoted = re.sub(r"\s*\n\s*(?:#|//)?\s*", " ", m.group(1)).rstrip(".…, ")
                if not any(lead.startswith(quoted) for lead in leads):
                    number = source.count("\n", 0, m.start()) + 1
                    broken.append(f"{os.path.relpath(path, root)}:{number}: docs/measurements.md "
                                  f"has no section \"{quoted}\"")
    return broken


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true",
                        help="compare instead of rewriting; exit 1 on a difference")
    parser.add_argument("--doc", action="append",
                        help="a doc to render or check (repeatable; default README.md and "
                             "docs/measurements.md)")
    parser.add_argument("--data", default=os.path.join(ROOT, "tests", "data", "measurements"),
                        help="the folder of the tables' CSV files")
    args = parser.parse_args()

    docs = args.doc or [os.path.join(ROOT, d) for d in DOCS]
    differs = []
    try:
        for doc in docs:
            if not os.path.isfile(doc):
                raise BadInput(f"{doc}: no such doc")
            with open(doc, encoding="utf-8") as f:
                text = f.read()
            lines = text.split("\n")
            with_contents = os.path.basename(doc) == os.path.basename(CONTENTS_DOC)
            rendered = "\n".join(render_doc(doc, lines, args.data, with_contents))
            if rendered == text:
                continue
            if args.check:
                differs.append(doc)
                sys.stdout.writelines(difflib.unified_diff(
                    text.splitlines(True), rendered.splitlines(True), doc, doc + " (from the data)"))
            else:
                tmp = doc + ".new"
                with open(tmp, "w", encoding="utf-8") as f:
                    f.write(rendered)
                os.replace(tmp, doc)
                print(f"rewrote {os.path.relpath(doc, ROOT)}")
    except BadInput as e:
        print(f"update-measurement-tables: {e}", file=sys.stderr)
        return 2

    status = 0
    for doc in differs:
        print(f"{doc} differs from what tests/data/measurements gives: "
              "run scripts/update-measurement-tables.py", file=sys.stderr)
        status = 1
    anchor_docs = sorted(
        ["README.md"] + [os.path.join("docs", d) for d in os.listdir(os.path.join(ROOT, "docs"))
                         if d.endswith(".md")]) if not args.doc else [
        os.path.relpath(d, ROOT) for d in args.doc]
    problems = check_anchors(ROOT, anchor_docs)
    if not args.doc:
        problems += check_quoted_sections(ROOT)
    for problem in problems:
        print(problem, file=sys.stderr)
        status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
