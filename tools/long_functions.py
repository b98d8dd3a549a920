#!/usr/bin/env python3
"""List the functions longer than a limit (default 100 lines) in C++ sources.

Usage: tools/long_functions.py [--limit N] [files...]
Without files it scans include/shadowkit/*.hpp and samples/report/main.cpp
(relative to the repository root). A brace-matching scan: comments, strings
and character literals are blanked first; a '{' opens a function body when
the text before it ends with ')' plus optional qualifiers (const, noexcept,
override, a trailing return type, a constructor's initializer list) and the
name before the matching '(' is not a control keyword. Lambdas and functions
nested in a function count toward the enclosing function only. Length counts
the lines from the line of the name to the closing brace.
Exit status 1 when any function is over the limit.
"""
import glob
import os
import re
import sys

CONTROL = {"if", "for", "while", "switch", "catch", "return", "sizeof",
           "alignof", "decltype", "noexcept", "static_assert", "defined",
           "requires", "constexpr"}


def blank(text):
    """Replace comments, strings and char literals by spaces (keep newlines)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            if m:
                end = text.find(")" + m.group(1) + '"', i)
                j = n if end < 0 else end + len(m.group(1)) + 2
                out.append(re.sub(r"[^\n]", " ", text[i:j]))
                i = j
            else:
                out.append(c)
                i += 1
        elif c in "\"'":
            # skip digit separators like 1'000
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum() \
                    and (i + 2 >= n or text[i + 2] != "'"):
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def match_back(s, close):
    """Index of the '(' matching the ')' at close."""
    depth = 0
    for k in range(close, -1, -1):
        if s[k] == ")":
            depth += 1
        elif s[k] == "(":
            depth -= 1
            if depth == 0:
                return k
    return -1


QUAL = re.compile(r"(\s*(const|noexcept(\s*\([^()]*\))?|override|final|mutable|&&|&|"
                  r"->\s*[\w:<>,\s\*&]+))*\s*$")


def function_name(s, brace):
    """Name of the function whose body opens at s[brace], or None."""
    head = s[max(0, brace - 4000):brace]  # a bounded window: the regexes stay linear
    # constructor initializer list: ') : a(x), b{y}' -> strip back to ')' before ':'
    stripped = head.rstrip()
    m = QUAL.search(stripped)
    core = stripped[:m.start()] if m else stripped
    core = core.rstrip()
    if not core.endswith(")"):
        # maybe an initializer list ending with ')' or '}' - try to find ') :'
        mi = re.search(r"\)\s*(noexcept\s*)?:\s*[\w:]+\s*[({][^;{}]*$", stripped)
        if not mi:
            return None
        core = stripped[:mi.start() + 1]
    open_ = match_back(core, len(core) - 1)
    if open_ < 0:
        return None
    before = core[:open_].rstrip()
    mname = re.search(r"(operator\s*\S+|~?[A-Za-z_]\w*(::~?[A-Za-z_]\w*)*)\s*(<[^;{}()]*>)?$", before)
    if not mname:
        return None
    name = mname.group(1)
    last = name.split("::")[-1]
    if last in CONTROL:
        return None
    # a macro-like call followed by a block, or a declaration with braces init
    prev = before[:mname.start()].rstrip()
    offset = brace - len(head)
    if prev.endswith("]"):
        return None  # lambda with name? unlikely
    if prev.endswith("=") or prev.endswith("(") or prev.endswith(","):
        return None
    return name, offset + mname.start()


def scan(path, limit):
    text = open(path, encoding="utf-8").read()
    s = blank(text)
    line_of = [0] * (len(s) + 1)
    ln = 1
    for i, ch in enumerate(s):
        line_of[i] = ln
        if ch == "\n":
            ln += 1
    line_of[len(s)] = ln
    found = []
    i, n = 0, len(s)
    while i < n:
        if s[i] == "{":
            fn = function_name(s, i)
            if fn:
                depth, j = 0, i
                while j < n:
                    if s[j] == "{":
                        depth += 1
                    elif s[j] == "}":
                        depth -= 1
                        if depth == 0:
                            break
                    j += 1
                first, last = line_of[fn[1]], line_of[j]
                found.append((last - first + 1, fn[0], first, last))
                i = j + 1
                continue
        i += 1
    return [f for f in found if f[0] > limit]


def main(argv):
    limit = 100
    files = []
    k = 0
    while k < len(argv):
        if argv[k] == "--limit":
            limit = int(argv[k + 1])
            k += 2
        else:
            files.append(argv[k])
            k += 1
    if not files:
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        files = sorted(glob.glob(os.path.join(root, "include/shadowkit/*.hpp")))
        files.append(os.path.join(root, "samples/report/main.cpp"))
    bad = 0
    for f in files:
        for length, name, first, last in scan(f, limit):
            print(f"{os.path.relpath(f)}:{first}-{last}: {name} {length} lines")
            bad += 1
    print(f"{bad} function(s) longer than {limit} lines", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
