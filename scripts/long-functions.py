#!/usr/bin/env python3
"""Lists the functions of the C++ sources longer than a number of lines (default 100).

  scripts/long-functions.py [LINES] [FOLDER...]    (default: every folder but build/ and tests/)

A function's length is the lines from its opening to its closing brace, both counted: one more
than clang-tidy's readability-function-size counts. The sources are read as text (comments and
literals blanked, braces matched), not compiled, so this takes a second where clang-tidy takes
minutes; it is a list to look at. A function-local lambda or class counts in its function.
"""
import os
import re
import sys

KEYWORDS = r"^(if|for|while|switch|catch|return|else|do|try)\b"


def blank_comments_and_literals(src):
    """src with comments, string and character literals blanked; newlines kept."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("//", i):
            j = src.find("\n", i)
            i = n if j < 0 else j
            continue
        if src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * src.count("\n", i, j))
            i = j
            continue
        raw = re.match(r'R"([^(\s]*)\(', src[i:i + 40])
        if raw and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == "_")):
            end = ")" + raw.group(1) + '"'
            j = src.find(end, i + raw.end())
            j = n if j < 0 else j + len(end)
            out.append('""' + "\n" * src.count("\n", i, j))
            i = j
            continue
        c = src[i]
        # A quote after a digit is a digit separator (1'000), not a character literal.
        if c == '"' or (c == "'" and not (i > 0 and src[i - 1].isalnum())):
            j = i + 1
            while j < n and src[j] != c:
                j += 2 if src[j] == "\\" else 1
            out.append('""')
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def without_templates(text):
    """text without leading template<...> heads."""
    return re.sub(r"^(\s*template\s*<[^<>]*(<[^<>]*>[^<>]*)*>\s*)+", "", text)


def functions(path):
    """(lines, name, first line) of every function defined in the file."""
    with open(path, encoding="utf-8") as f:
        s = blank_comments_and_literals(f.read())
    found, stack = [], []  # stack: (kind, line, name); kinds: F function, I member init, other
    line, head = 1, 0  # head: where the text before the next brace starts
    for i, c in enumerate(s):
        if c == "\n":
            line += 1
        elif c == "{":
            before = " ".join(s[head:i].split())
            kind, name = "B", ""
            if not any(k == "F" for k, _, _ in stack):
                text = without_templates(before)
                paren = text.rfind(")")
                if re.search(r"\b(namespace|class|struct|enum|union)\b", text.split("(")[0]) or \
                        re.match(r'^extern\s*""$', text):
                    kind = "C"
                elif text.endswith("="):  # an initializer or a default argument's braces
                    kind = "I"
                elif paren >= 0 and not re.match(KEYWORDS, text):
                    # Foo::Foo(...) : member_{...}: a member's braces before the body's.
                    tail = text[paren + 1:]
                    if re.match(r"\s*(noexcept\s*)?:[^:]", tail) and re.search(r"[\w>]\s*$", tail):
                        kind = "I"
                    else:
                        kind = "F"
                        names = re.findall(r"([~\w:]+)\s*\(", text)
                        name = names[0] if names else text[:40]
            stack.append((kind, line, name))
            if kind != "I":
                head = i + 1
        elif c == "}":
            kind, first, name = stack.pop() if stack else ("B", line, "")
            if kind == "F":
                found.append((line - first + 1, name, first))
            if kind != "I":
                head = i + 1
        elif c == ";":
            head = i + 1
    return found


def main():
    args = sys.argv[1:]
    limit = int(args.pop(0)) if args and args[0].isdigit() else 100
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    folders = args or [os.path.join(root, d) for d in sorted(os.listdir(root))
                       if os.path.isdir(os.path.join(root, d)) and not d.startswith(".")
                       and d not in ("build", "tests")]
    rows = []
    for folder in folders:
        for place, _, files in os.walk(folder):
            for name in files:
                if name.endswith((".cpp", ".hpp")):
                    path = os.path.join(place, name)
                    for lines, function, first in functions(path):
                        rows.append((lines, function, os.path.relpath(path, root), first))
    for lines, function, path, first in sorted(rows, key=lambda r: (-r[0], r[2], r[3])):
        if lines > limit:
            print(f"{lines:5d}  {function}  {path}:{first}")


if __name__ == "__main__":
    main()
