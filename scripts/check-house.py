#!/usr/bin/env python3
"""What keeps the house (docs/design.md §1, CONTRIBUTING.md): run by CI, exits 1 on a breach.

  - no source file over 600 lines, no function over 120 (C++: counted from the line of its opening
    brace to the line of its closing one, at namespace or class scope; a class body is not a function);
  - the README at most 300 lines, and every file the README or docs/ link to ships;
  - the arrows of docs/design.md §1: a folder includes only the folders below it, and Bullet only
    physics/;
  - nothing links dw_app but the dwatch executable (read from CMake's graph of targets, when a
    build folder is given: scripts/check-house.py [BUILD_DIR]).
"""
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
MAX_FILE, MAX_FUNCTION, MAX_README = 600, 120, 300
SOURCE = {".cpp", ".h", ".py", ".pyi", ".sh", ".in"}
# The arrows of docs/design.md §1: the folders each folder's sources may include (tests/ may
# include anything). Nothing includes app/ but app/.
BELOW = {
    "watch": {"watch"},
    "sim": {"watch", "sim"},
    "physics": {"watch", "sim", "physics"},
    "render": {"watch", "sim", "render"},
    "scenarios": {"watch", "sim", "physics", "scenarios"},
    "dist": {"watch", "sim", "dist"},
    "shell": {"watch", "sim", "physics", "render", "scenarios", "shell"},
    "bench": {"watch", "sim", "physics", "render", "scenarios", "dist", "shell", "bench"},
    "python": {"watch", "sim", "physics", "render", "scenarios", "shell", "python"},
    "app": {"watch", "sim", "physics", "render", "scenarios", "dist", "shell", "bench", "app"},
}

# Left as they are on purpose, each with its reason; the list only shrinks.
# Files allowed a longer function, each with why (none today).
KNOWN: dict[str, str] = {}


def tracked_sources():
    out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout.split("\n")
    for name in out:
        path = ROOT / name
        if name and path.suffix in SOURCE and path.is_file() and not name.split("/")[0].startswith("build"):
            yield path


def strip_code(text):
    """C++ text with comments, strings and character literals blanked (newlines kept)."""
    pattern = re.compile(r'//[^\n]*|/\*.*?\*/|R"(\w*)\(.*?\)\1"|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
    return pattern.sub(lambda m: "\n" * m.group(0).count("\n") + " ", text)


def long_functions(path):
    """(first line, lines) of each function body at namespace or class scope longer than MAX_FUNCTION."""
    code = strip_code(path.read_text(errors="replace"))
    found, stack, head_start, line = [], [], 0, 1
    for i, c in enumerate(code):
        if c == "\n":
            line += 1
        elif c == "{":
            head = code[head_start:i]
            at_namespace = all(kind in ("namespace", "class") for kind, _ in stack)
            if re.search(r"\bnamespace\b|extern\s*$", head) and at_namespace:
                kind = "namespace"
            elif at_namespace and re.search(r"\b(class|struct|union)\b[^()]*$", head):
                kind = "class"
            elif at_namespace and not re.search(r"\benum\b|=\s*$", head) and ")" in head:
                kind = "function"
            else:
                kind = "block"
            stack.append((kind, line))
            head_start = i + 1
        elif c == "}":
            if stack:
                kind, start = stack.pop()
                if kind == "function" and line - start + 1 > MAX_FUNCTION:
                    found.append((start, line - start + 1))
            head_start = i + 1
        elif c == ";":
            head_start = i + 1
    return found


def wrong_arrows(path, rel):
    """#include lines of a source that point up the house or sideways (BELOW)."""
    allowed = BELOW.get(rel.parts[0])
    if allowed is None:
        return []
    found = []
    for n, line in enumerate(path.read_text(errors="replace").split("\n"), 1):
        m = re.match(r'\s*#\s*include\s+"([a-z_]+)/', line)
        if m and m.group(1) in BELOW and m.group(1) not in allowed:
            found.append(f"{rel}:{n}: {rel.parts[0]}/ includes {m.group(1)}/ (docs/design.md §1: the arrows)")
        # Bullet is physics/'s own: no other folder sees its headers.
        if rel.parts[0] != "physics" and re.match(r"\s*#\s*include\s+<(Bullet\w*|LinearMath)/", line):
            found.append(f"{rel}:{n}: Bullet is included outside physics/ (docs/design.md §1)")
    return found


def linked_docs():
    """Files named by a Markdown link in the README, CONTRIBUTING.md and docs/ that do not exist."""
    missing = []
    for doc in [ROOT / "README.md", ROOT / "CONTRIBUTING.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        if not doc.exists():
            continue
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", doc.read_text()):
            if re.match(r"[a-z]+:", target):
                continue
            if not (doc.parent / target).exists():
                missing.append(f"{doc.relative_to(ROOT)}: links to {target}, which does not ship")
    return missing


def links_into_app(build):
    """Targets other than dwatch that link dw_app, from CMake's --graphviz output."""
    dot = build / "house-graph" / "targets.dot"
    dot.parent.mkdir(exist_ok=True)
    subprocess.run(["cmake", f"--graphviz={dot}", "."], cwd=build, check=True, capture_output=True)
    text = dot.read_text()
    names = dict(re.findall(r'"(node\d+)"\s*\[\s*label\s*=\s*"([^"]+)"', text))
    bad = []
    for a, b in re.findall(r'"(node\d+)"\s*->\s*"(node\d+)"', text):
        if names.get(b) == "dw_app" and names.get(a) != "dwatch":
            bad.append(f"{names.get(a)} links dw_app (only the dwatch executable may)")
    return bad


def main():
    problems = []
    for path in tracked_sources():
        rel = path.relative_to(ROOT)
        lines = path.read_text(errors="replace").count("\n")
        if lines > MAX_FILE:
            problems.append(f"{rel}: {lines} lines (at most {MAX_FILE}: one job a file)")
        if path.suffix in {".cpp", ".h"}:
            problems += wrong_arrows(path, rel)
        if path.suffix in {".cpp", ".h"} and str(rel) not in KNOWN:
            for start, length in long_functions(path):
                problems.append(f"{rel}:{start}: a function of {length} lines (at most {MAX_FUNCTION})")
    readme = (ROOT / "README.md").read_text().count("\n")
    if readme > MAX_README:
        problems.append(f"README.md: {readme} lines (at most {MAX_README}: the reference lives in docs/)")
    problems += linked_docs()
    if len(sys.argv) > 1:
        problems += links_into_app(pathlib.Path(sys.argv[1]).resolve())
    for p in problems:
        print(f"check-house: {p}")
    print(f"check-house: {'ok' if not problems else str(len(problems)) + ' problems'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
