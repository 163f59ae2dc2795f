#!/usr/bin/env python3
"""Every relative link in the repository's Markdown resolves: the file or folder exists, and an
anchor (#...) names a heading of the target page, as GitHub spells heading anchors.

Usage: check_docs_links.py [ROOT]   (default: the repository holding this script)
Prints each broken link as FILE:LINE: TARGET: WHY and exits 1 if there is any.
Links to other sites (http:, https:, mailto:) are not followed. Fenced code blocks and inline
code spans are skipped: their brackets are not links.
"""
import os
import re
import subprocess
import sys

LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
REF_DEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s{0,3}(```|~~~)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
HTML_ANCHOR = re.compile(r"<a\s+(?:name|id)=\"([^\"]+)\"")


def markdown_files(root):
    """The tracked and untracked-but-not-ignored *.md files; every *.md outside build folders
    when ROOT is not a git checkout."""
    try:
        out = subprocess.run(
            ["git", "-C", root, "ls-files", "-z", "--cached", "--others", "--exclude-standard",
             "--", "*.md"], check=True, capture_output=True).stdout
        names = sorted({n for n in out.decode().split("\0") if n})
        return [n for n in names if os.path.isfile(os.path.join(root, n))]
    except (OSError, subprocess.CalledProcessError):
        found = []
        for d, dirs, files in os.walk(root):
            dirs[:] = [x for x in dirs if not x.startswith(".") and not x.startswith("build")
                       and not os.path.exists(os.path.join(d, x, "CMakeCache.txt"))]
            found += [os.path.relpath(os.path.join(d, f), root) for f in files if f.endswith(".md")]
        return sorted(found)


def prose_lines(text):
    """(line number, line) outside fenced code blocks, with inline code spans blanked."""
    fence = None
    for number, line in enumerate(text.splitlines(), 1):
        m = FENCE.match(line)
        if m:
            if fence is None:
                fence = m.group(1)
            elif m.group(1) == fence:
                fence = None
            continue
        if fence is None:
            yield number, CODE_SPAN.sub(lambda s: " " * len(s.group(0)), line)


def slug(heading):
    """GitHub's anchor of a heading: the rendered text, lower case, punctuation dropped (letters,
    digits, '_' and '-' kept), each space a '-'."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)   # a link's text only
    text = text.replace("`", "").replace("*", "")
    text = re.sub(r"<[^>]+>", "", text).lower()
    text = "".join(c for c in text if c.isalnum() or c in " _-")
    return text.replace(" ", "-")


def anchors(path, cache):
    if path not in cache:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        seen, names = {}, set()
        fence = None
        for line in text.splitlines():
            m = FENCE.match(line)
            if m:
                fence = m.group(1) if fence is None else (None if m.group(1) == fence else fence)
                continue
            if fence is not None:
                continue
            names.update(HTML_ANCHOR.findall(line))
            h = HEADING.match(line)
            if h:
                base = slug(h.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                names.add(base if n == 0 else "%s-%d" % (base, n))
        cache[path] = names
    return cache[path]


def check(root):
    problems, cache, count = [], {}, 0
    for name in markdown_files(root):
        source = os.path.join(root, name)
        with open(source, encoding="utf-8") as f:
            text = f.read()
        for number, line in prose_lines(text):
            targets = [m.group(1) for m in LINK.finditer(line)]
            d = REF_DEF.match(line)
            if d:
                targets.append(d.group(1))
            for target in targets:
                if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):
                    continue   # another site, or mailto:
                count += 1
                path, _, anchor = target.partition("#")
                where = "%s:%d: %s" % (name, number, target)
                resolved = source if not path else os.path.normpath(
                    os.path.join(os.path.dirname(source), path))
                if path.startswith("/"):
                    problems.append(where + ": absolute path (links must be relative)")
                elif not os.path.exists(resolved):
                    problems.append(where + ": no such file or folder")
                elif anchor:
                    if not resolved.endswith(".md") or not os.path.isfile(resolved):
                        problems.append(where + ": an anchor into a file that is not Markdown")
                    elif anchor not in anchors(resolved, cache):
                        problems.append(where + ": no heading with that anchor in "
                                        + os.path.relpath(resolved, root))
    return count, problems


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                           os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    count, problems = check(root)
    for p in problems:
        print(p)
    print("%d relative links checked, %d broken" % (count, len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
