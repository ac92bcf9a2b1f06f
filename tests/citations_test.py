"""The project's citations stand alone and resolve.

1. No file of the project names the external working notes the maps were first derived in (the
   notes' file name, or a "shared" folder of some machine): the project's own reference is
   docs/maps.md.
2. Every section cited as "docs/maps.md", the section sign and a number N (or N.M; also lists of
   them after it, separated by commas or "and"), and every section sign with a number inside
   docs/maps.md, names a heading of docs/maps.md ("## N. ..." or "### N.M ..."). Outside
   docs/maps.md the section sign may only appear in such a citation.
3. Every erratum cited by number, "E" and the number ("erratum E<n>", "errata E<n>, E<m>", a range
   "E<n>-E<m>" or "E<n>–E<m>", or a bare "(E<n>)"), is listed in the errata index, section 9 of
   docs/maps.md.

Run as /usr/bin/python3 -B tests/citations_test.py (stdlib only). The repository root is
$QMAPS_SOURCE_DIR, else this file's parent's parent. The files checked are those git knows
(tracked, and untracked but not ignored), else every file under the root but build*/ and .git/.
"""
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(os.environ.get("QMAPS_SOURCE_DIR") or Path(__file__).resolve().parent.parent)
MAPS = "docs/maps.md"
ERRATA_SECTION = "9"
# Spelled in pieces so that this file does not contain them.
FORBIDDEN = ("MAPS" ".md", "shared" "/")

HEADING = re.compile(r"^#{2,6}\s+(\d+(?:\.\d+)*)\.?\s")
SIGN = "\u00a7"  # the section sign, spelled so that this file cites nothing itself
# A citation: "docs/maps.md" then the sign and N; the link forms "[maps.md](maps.md)" and
# "(maps.md)" before the sign; and a list after it, the sign and a number each time.
CITATION = re.compile(r"maps\.md(?:\]\([^)\s]*\))?\)?\s*(?=\u00a7)")
SECTION = re.compile(r"\u00a7\s?(\d+(?:\.\d+)*)([A-Za-z]\w*)?")
LIST_SEP = re.compile(r"\s*(?:,\s*and|,|and|&)\s*(?=\u00a7)")
# Erratum numbers: "E" and one or two digits, or a range of them ("-", en dash). Not part of a
# longer word, of a number (1E5) or of a linter code after "noqa".
ERRATUM = re.compile(r"(?<![\w.])E(\d{1,2})(?:\s*[-–—‑]\s*E?(\d{1,2}))?(?![\w])")
ERRATA_ROW = re.compile(r"^\|\s*E(\d+)\s*\|")


def project_files():
    """Relative paths of the files to check."""
    try:
        out = subprocess.run(
            ["git", "-C", str(ROOT), "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            capture_output=True, check=True).stdout.decode("utf-8", "surrogateescape")
        names = sorted({n for n in out.split("\0") if n})
    except (OSError, subprocess.CalledProcessError):
        names = []
        for dirpath, dirnames, filenames in os.walk(ROOT):
            rel = Path(dirpath).relative_to(ROOT)
            dirnames[:] = sorted(d for d in dirnames
                                 if d != ".git" and not (rel == Path(".") and d.startswith("build")))
            names += [str(rel / f) if rel != Path(".") else f for f in sorted(filenames)]
    return [n for n in names if not n.startswith("build") and (ROOT / n).is_file()]


def text_of(name):
    """The file's text, or None for a binary file."""
    data = (ROOT / name).read_bytes()
    if b"\0" in data[:8192]:
        return None
    return data.decode("utf-8", "replace")


def maps_headings(text):
    return {m.group(1) for line in text.splitlines() if (m := HEADING.match(line))}


def errata_index(text):
    """The numbers listed by the table of the errata index section."""
    listed, inside = set(), False
    for line in text.splitlines():
        if line.startswith("## "):
            m = HEADING.match(line)
            inside = bool(m and m.group(1) == ERRATA_SECTION)
        elif inside and (m := ERRATA_ROW.match(line)):
            listed.add(int(m.group(1)))
    return listed


def cited_sections(line, in_maps):
    """(label, column) of each section cited on the line, and the stray section signs."""
    cited, covered = [], set()
    for m in CITATION.finditer(line):
        pos = m.end()
        while True:
            s = SECTION.match(line, pos)
            if not s:
                break
            cited.append((s.group(1) + (s.group(2) or ""), s.start()))
            covered.add(s.start())
            sep = LIST_SEP.match(line, s.end())
            if not sep:
                break
            pos = sep.end()
    stray = []
    for s in SECTION.finditer(line):
        if s.start() in covered:
            continue
        if in_maps:
            cited.append((s.group(1) + (s.group(2) or ""), s.start()))
        else:
            stray.append(s.group(0))
    for i, ch in enumerate(line):
        if ch == SIGN and i not in covered and not SECTION.match(line, i):
            stray.append(SIGN)
    return cited, stray


def cited_errata(line):
    """Erratum numbers referred to on the line (ranges expanded)."""
    noqa = line.find("noqa")
    out = []
    for m in ERRATUM.finditer(line):
        if noqa != -1 and m.start() > noqa:
            continue
        first = int(m.group(1))
        last = int(m.group(2)) if m.group(2) else first
        out.append((m.group(0), list(range(first, last + 1)) if last >= first else [first, last]))
    return out


def main():
    files = project_files()
    texts = {}
    for name in files:
        t = text_of(name)
        if t is not None:
            texts[name] = t
    maps_text = texts.get(MAPS)

    results = []  # (check name, problems, what was checked)

    # (a) The external notes are never named.
    problems = []
    for name, text in texts.items():
        for no, line in enumerate(text.splitlines(), 1):
            for word in FORBIDDEN:
                if word in line:
                    problems.append(f"{name}:{no}: names '{word}' (cite docs/maps.md instead): "
                                    f"{line.strip()[:120]}")
    results.append(("no external notes named", problems, f"{len(texts)} text files"))

    # The reference itself: present, numbered 1..9, with an errata index.
    problems = []
    if maps_text is None:
        problems.append(f"{MAPS}: missing")
        headings, listed = set(), set()
    else:
        headings, listed = maps_headings(maps_text), errata_index(maps_text)
        for n in range(1, 10):
            if str(n) not in headings:
                problems.append(f"{MAPS}: no heading '## {n}. ...'")
        if not listed:
            problems.append(f"{MAPS}: {SIGN}{ERRATA_SECTION} lists no errata (rows '| E<n> | ...')")
    results.append((f"{MAPS} has sections 1-9 and an errata index", problems,
                    f"{len(headings)} headings, {len(listed)} errata listed"))

    # (b) Every cited section exists; no stray section sign.
    problems, count = [], 0
    for name, text in texts.items():
        in_maps = name == MAPS
        for no, line in enumerate(text.splitlines(), 1):
            if SIGN not in line:
                continue
            cited, stray = cited_sections(line, in_maps)
            for label, _ in cited:
                count += 1
                if label not in headings:
                    problems.append(f"{name}:{no}: {SIGN}{label} is not a heading of {MAPS}: "
                                    f"{line.strip()[:120]}")
            for s in stray:
                problems.append(f"{name}:{no}: '{s}' is not part of a '{MAPS} {SIGN}N' citation: "
                                f"{line.strip()[:120]}")
    if count == 0:
        problems.append("no section citation found at all (is the parser broken?)")
    results.append(("section citations resolve", problems, f"{count} citations"))

    # (c) Every cited erratum is listed in the errata index.
    problems, count = [], 0
    for name, text in texts.items():
        for no, line in enumerate(text.splitlines(), 1):
            for token, numbers in cited_errata(line):
                count += 1
                missing = [n for n in numbers if n not in listed]
                if missing:
                    problems.append(f"{name}:{no}: {token}: "
                                    + ", ".join(f"E{n}" for n in missing)
                                    + f" not listed in {MAPS} {SIGN}{ERRATA_SECTION}: "
                                    + line.strip()[:120])
    if count == 0:
        problems.append("no erratum citation found at all (is the parser broken?)")
    results.append((f"errata cited are listed in {MAPS} {SIGN}{ERRATA_SECTION}", problems,
                    f"{count} references"))

    passed = failed = 0
    for name, problems, what in results:
        if problems:
            failed += 1
            print(f"FAIL {name}:")
            for p in problems:
                print(f"  {p}")
        else:
            passed += 1
            print(f"ok   {name} ({what})")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
