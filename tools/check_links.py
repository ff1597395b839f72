#!/usr/bin/env python3
"""Checks the repository's cross references: links, cited headings, page sizes.

Usage: /usr/bin/python3 tools/check_links.py [ROOT]

ROOT defaults to the repository holding this script. The files checked are
those git tracks or would (`git ls-files --cached --others
--exclude-standard`), or, where ROOT is not a git work tree (a copy or a
source archive), every file under it but build folders and hidden ones.
Prints one line per problem, `FILE:LINE: what`, and exits 1 if there was any.

(a) Every relative link of every Markdown file (`[text](target)`,
    `[label]: target`, images alike; outside code) names a file or folder
    that exists, and a `#anchor` on a Markdown file names one of its
    headings' GitHub slugs (lowercase, spaces to '-', punctuation other than
    '-' and '_' removed, '-1', '-2' ... for repeats; `<a id>` and `<a name>`
    count too). Links with a scheme (https:, mailto:) are not followed.
(b) Every citation `<page>.md, "<heading>"` (or `... "<heading>" and
    "<another>"`) in any text file names an existing file with such a
    heading. Also found: ':' for ',', the path in backticks or as a
    Markdown link's target, the quotes escaped in a string literal, and a
    citation wrapped over lines, where a comment's continuation lines begin
    with `//`, `#`, `*` or the like and a path may break after a '/'. The
    path is taken from ROOT, else from the citing file's folder (a link's
    target from its folder). Headings compare case-insensitively, with
    whitespace collapsed and backticks and emphasis removed; a heading may
    be cited by its text up to a ': ' or ' (' ("Rendering" for "Rendering:
    `render`, `compare`") and without its number ("Modules" for "1.
    Modules"), and a paragraph's bold run-in head (`**The set cache.**`,
    not a bold link) counts as a heading of its page.
(c) No Markdown file has more than 1100 lines, and
    tools/experiments/README.md (the index of the experiment pages) no more
    than 600.
(d) No source file (C, C++, Python, shell) has more than 500 lines: a
    file a reader takes in whole.
"""
import bisect
import os
import re
import subprocess
import sys

MAX_MD_LINES = 1100
INDEX = "tools/experiments/README.md"
MAX_INDEX_LINES = 600
MAX_SOURCE_LINES = 500
SOURCE_EXT = (".c", ".h", ".cpp", ".py", ".sh")

SKIP_EXT = {".png", ".jpg", ".jpeg", ".exr", ".hdr", ".pfm", ".ptsb", ".nuldnet",
            ".ply", ".glb", ".gz", ".zip", ".pdf", ".bin", ".so", ".a", ".o"}


def tracked_files(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z", "--cached", "--others",
                              "--exclude-standard"], capture_output=True,
                             check=True).stdout
        inside = subprocess.run(["git", "-C", root, "rev-parse", "--show-prefix"],
                                capture_output=True, check=True).stdout.strip()
        if inside:  # ROOT is a folder inside some other repository: walk it instead
            raise ValueError
        return [f for f in out.decode("utf-8", "replace").split("\0")
                if f and os.path.isfile(os.path.join(root, f))]
    except (OSError, subprocess.CalledProcessError, ValueError):
        files = []
        for d, dirs, names in os.walk(root):
            dirs[:] = sorted(x for x in dirs
                             if not x.startswith(".") and not x.startswith("build"))
            rel = os.path.relpath(d, root)
            for n in sorted(names):
                files.append(n if rel == "." else os.path.join(rel, n).replace(os.sep, "/"))
        return files


def read_text(path):
    if os.path.splitext(path)[1].lower() in SKIP_EXT:
        return None
    try:
        with open(path, "rb") as f:
            data = f.read(4 << 20)
    except OSError:
        return None
    if b"\0" in data[:8192]:
        return None
    return data.decode("utf-8", "replace")


# --- Markdown structure -------------------------------------------------------

FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
ATX = re.compile(r"^ {0,3}(#{1,6})[ \t]+(.*?)(?:[ \t]+#+)?[ \t]*$")
RUN_IN = re.compile(r"^\s*(?:[*+-]\s+|\d+\.\s+)?\*\*(.+?)\*\*")
HTML_ANCHOR = re.compile(r"""<a\s[^>]*?(?:id|name)\s*=\s*["']([^"']+)["']""", re.I)


def code_masked(text):
    """The text with fenced and indented code blocks and inline code spans
    blanked (newlines kept), so links and headings are only read in prose."""
    lines = text.split("\n")
    out = []
    fence = None
    prev_blank = True
    in_indented = False
    for line in lines:
        m = FENCE.match(line)
        if fence:
            out.append("")
            if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence):
                fence = None
            continue
        if m:
            fence = m.group(1)
            out.append("")
            continue
        blank = not line.strip()
        if (line.startswith("    ") or line.startswith("\t")) and (prev_blank or in_indented) \
                and not blank:
            in_indented = True
            out.append("")
            continue
        if not blank:
            in_indented = False
        prev_blank = blank
        out.append(line)
    masked = "\n".join(out)
    # Inline code spans (a span may not cross a blank line).
    return re.sub(r"(`+)(?:(?!\n\s*\n).)+?\1",
                  lambda m: re.sub(r"[^\n]", " ", m.group(0)), masked, flags=re.S)


def plain_heading(text):
    """A heading's text as rendered: links to their text, no markup."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = text.replace("`", "")
    text = re.sub(r"(\*\*|__)(.+?)\1", r"\2", text)
    text = re.sub(r"(?<!\w)[*_](.+?)[*_](?!\w)", r"\1", text)
    return text.strip()


def slug(text):
    s = plain_heading(text).lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def norm(text):
    return re.sub(r"\s+", " ", plain_heading(text)).strip().lower()


class Page:
    """A Markdown file's heading slugs and the names it may be cited by."""

    def __init__(self, text):
        self.slugs = set()
        self.names = set()
        seen = {}
        lines = text.split("\n")
        fence = None
        for i, line in enumerate(lines):
            m = FENCE.match(line)
            if fence:
                if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence):
                    fence = None
                continue
            if m:
                fence = m.group(1)
                continue
            h = ATX.match(line)
            if not h and i + 1 < len(lines) and line.strip() and \
                    re.match(r"^ {0,3}(=+|-+)\s*$", lines[i + 1]) and \
                    not line.lstrip().startswith(("*", "-", "|", ">")):
                h = (None, line.strip())  # setext
                title = line.strip()
            elif h:
                title = h.group(2)
            if h:
                s = slug(title)
                n = seen.get(s, 0)
                seen[s] = n + 1
                self.slugs.add(s if n == 0 else f"{s}-{n}")
                self.add_name(title)
                continue
            r = RUN_IN.match(line)
            if r and "](" not in r.group(1) and (
                    i == 0 or not lines[i - 1].strip() or
                    re.match(r"^\s*(?:[*+-]|\d+\.)\s", line)):
                self.add_name(r.group(1).rstrip(".:").strip())
        for a in HTML_ANCHOR.findall(text):
            self.slugs.add(a)

    def add_name(self, title):
        full = norm(title)
        for name in (full, re.sub(r"^\d+(?:\.\d+)*\.?\s+", "", full)):
            self.names.add(name)
            for sep in (": ", " ("):
                if sep in name:
                    self.names.add(name.split(sep, 1)[0].strip())


# --- the checks ----------------------------------------------------------------

LINK = re.compile(r"!?\[((?:[^\[\]]|\[[^\[\]]*\])*)\]"
                  r"\(\s*(<[^>\n]*>|[^\s()]*(?:\([^\s()]*\)[^\s()]*)*)"
                  r"(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^)]*\)))?\s*\)")
REFDEF = re.compile(r"^ {0,3}\[[^\]]+\]:\s*(\S+)", re.M)
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")

# A comment's continuation marker at the start of a line.
MARKER = re.compile(r"^\s*(?:///?|/\*+|\*+(?=\s|$)|#+(?=\s|$|!)|--|;+|%+)?\s*")
CITE = re.compile(r"(?P<link>\]\()?(?P<path>(?:[\w.-]+/)*[\w.-]*\w\.md)(?:#[\w-]*)?`?\)?"
                  r"[,:][ \t]*\\?\"(?P<head>[^\"\\\n]{1,200}?)\\?\"")

AND = re.compile(r"\s+and\s+\\?\"([^\"\\\n]{1,200}?)\\?\"")  # a second cited heading


class Checker:
    def __init__(self, root):
        self.root = os.path.abspath(root)
        self.problems = []
        self.pages = {}

    def page(self, rel):
        if rel not in self.pages:
            text = read_text(os.path.join(self.root, rel)) or ""
            self.pages[rel] = Page(text)
        return self.pages[rel]

    def report(self, rel, line, what):
        self.problems.append(f"{rel}:{line}: {what}")

    def rel_of(self, base_dir, target):
        """target (a path in the repository's '/' form) from base_dir, as a
        path relative to ROOT, or None where it leaves ROOT."""
        if target.startswith("/"):
            joined = target.lstrip("/")
        else:
            joined = os.path.join(base_dir, target)
        p = os.path.normpath(joined).replace(os.sep, "/")
        if p == ".":
            return ""
        if p.startswith("../") or p == "..":
            return None
        return p

    def exists(self, rel):
        return rel is not None and os.path.exists(os.path.join(self.root, rel))

    def check_links(self, rel, text):
        masked = code_masked(text)
        base = os.path.dirname(rel)
        starts = [0] + [m.end() for m in re.finditer("\n", masked)]

        def line_of(pos):
            return bisect.bisect_right(starts, pos)

        targets = [(m.start(2), m.group(2)) for m in LINK.finditer(masked)]
        targets += [(m.start(1), m.group(1)) for m in REFDEF.finditer(masked)]
        for pos, target in targets:
            target = target.strip("<>").strip()
            if not target or SCHEME.match(target) or target.startswith("//"):
                continue
            path, _, anchor = target.partition("#")
            path = path.split("?", 1)[0]
            line = line_of(pos)
            if path:
                dest = self.rel_of(base, path)
                if not self.exists(dest):
                    self.report(rel, line, f"link to a missing file: {target}")
                    continue
            else:
                dest = rel
            if anchor and dest.endswith(".md") and os.path.isfile(os.path.join(self.root, dest)):
                if anchor.lower() not in self.page(dest).slugs:
                    self.report(rel, line, f"link to a missing heading: {target}")

    def check_citations(self, rel, text):
        # Join the lines into one stream, each line's comment marker removed,
        # remembering where every line starts.
        parts, starts, pos = [], [], 0
        for line in text.split("\n"):
            piece = MARKER.sub("", line, count=1).rstrip()
            if parts:
                sep = "" if parts[-1].endswith("/") and piece[:1].isalnum() else " "
                parts.append(sep)
                pos += len(sep)
            starts.append(pos)
            parts.append(piece)
            pos += len(piece)
        joined = "".join(parts)
        if ".md" not in joined:
            return
        base = os.path.dirname(rel)
        for m in CITE.finditer(joined):
            path, head = m.group("path"), m.group("head")
            line = bisect.bisect_right(starts, m.start("path"))
            if m.group("link"):
                candidates = [self.rel_of(base, path)]
            else:
                candidates = [self.rel_of("", path), self.rel_of(base, path)]
            dest = next((c for c in candidates if self.exists(c)
                         and os.path.isfile(os.path.join(self.root, c))), None)
            if dest is None:
                self.report(rel, line, f'citation of a missing file: {path}, "{head}"')
                continue
            heads = [head]
            more = AND.match(joined, m.end())
            if more:
                heads.append(more.group(1))
            for h in heads:
                if norm(h) not in self.page(dest).names:
                    self.report(rel, line, f'citation of a missing heading: {dest}, "{h}"')

    def run(self):
        files = tracked_files(self.root)
        for rel in files:
            text = read_text(os.path.join(self.root, rel))
            if text is None:
                continue
            if rel.endswith(".md"):
                n = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
                if n > MAX_MD_LINES:
                    self.report(rel, n, f"{n} lines, more than {MAX_MD_LINES}")
                if rel == INDEX and n > MAX_INDEX_LINES:
                    self.report(rel, n, f"{n} lines, more than the index's {MAX_INDEX_LINES}")
                self.check_links(rel, text)
            elif rel.endswith(SOURCE_EXT):
                n = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
                if n > MAX_SOURCE_LINES:
                    self.report(rel, n, f"{n} lines, more than a source file's {MAX_SOURCE_LINES}")
            self.check_citations(rel, text)
        return self.problems


def main(argv):
    if len(argv) > 2 or (len(argv) == 2 and argv[1] in ("-h", "--help")):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    here = os.path.dirname(os.path.abspath(__file__))
    root = argv[1] if len(argv) == 2 else os.path.join(here, "..")
    if not os.path.isdir(root):
        print(f"check_links.py: {root} is not a folder", file=sys.stderr)
        return 2
    problems = Checker(root).run()
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
