#!/usr/bin/env python3
"""Link check of the user guide (standard library only).

    python3 tools/check_docs.py html BOOK_DIR SRC_DIR    # the built book (mdbook build)
    python3 tools/check_docs.py markdown FILE_OR_DIR...  # Markdown sources as they are

`html` reads every page mdBook wrote into BOOK_DIR and checks each internal `href` and
`src` (links, images, style sheets, scripts): the file must exist in the book, and a
`#fragment` must name an `id` (or `name`) on the target page. A link that leaves the
book (`../../examples/slurm/qc-array.sbatch` from a guide page) is resolved the way a
reader browsing the repository follows it: from the page's source file in SRC_DIR, and
the file must exist in the repository.

`markdown` checks the relative links and images of Markdown files (README.md, the
guide's pages) against the files beside them, with the same rule for fragments that
point into another Markdown file: the heading must exist (GitHub's and mdBook's
heading ids). Code blocks and code spans are skipped.

`generated` checks the pages the docs generate from the code (docs/reference/): one
top-level heading each, the title (a `# Safety` of a doc comment would be a chapter of
the book), and no rustdoc-style link (`[`Name`]` with no target, shown as brackets).

    python3 tools/check_docs.py generated FILE_OR_DIR...

Exit status 1 with one line per broken link (`FILE: TARGET: why`), 0 when every link
resolves.
"""
import os
import re
import sys
import urllib.parse
from html.parser import HTMLParser

EXTERNAL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")  # http:, https:, mailto:, data:...


class Page(HTMLParser):
    """The links and the ids of one HTML page."""

    LINK_ATTRS = {"a": "href", "link": "href", "img": "src", "script": "src",
                  "iframe": "src", "source": "src"}

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.links = []  # (line, url)
        self.ids = set()

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for key in ("id", "name"):
            if attrs.get(key):
                self.ids.add(attrs[key])
        want = self.LINK_ATTRS.get(tag)
        if want and attrs.get(want):
            self.links.append((self.getpos()[0], attrs[want]))

    handle_startendtag = handle_starttag


def read_page(path, cache):
    if path not in cache:
        page = Page()
        with open(path, encoding="utf-8", errors="replace") as f:
            page.feed(f.read())
        page.close()
        cache[path] = page
    return cache[path]


def check_html(book, src):
    """Broken links of the built book, as (file, line, url, why)."""
    book = os.path.realpath(book)
    src = os.path.realpath(src)
    repo = os.path.dirname(src)
    cache, broken, counts = {}, [], {"pages": 0, "links": 0, "repository": 0}
    for root, _, files in os.walk(book):
        for name in sorted(files):
            if not name.endswith(".html"):
                continue
            path = os.path.join(root, name)
            # print.html is every chapter on one page, with links rewritten by mdBook's
            # script; 404.html is served from the site root. Both repeat the chapters'
            # links, so the chapters' own pages are what is checked.
            if os.path.relpath(path, book) in ("print.html", "404.html", "toc.html"):
                continue
            counts["pages"] += 1
            page = read_page(path, cache)
            for line, url in page.links:
                counts["links"] += 1
                why = check_html_link(book, repo, src, path, url, cache, counts)
                entry = (os.path.relpath(path, book), line, url, why)
                # mdBook writes each Markdown image twice (the image and its zoomed
                # copy): one report per link and line.
                if why and entry not in broken:
                    broken.append(entry)
    return broken, counts


def check_html_link(book, repo, src, page_path, url, cache, counts):
    if EXTERNAL.match(url) or url.startswith("//"):
        return None
    parts = urllib.parse.urlsplit(url)
    target = urllib.parse.unquote(parts.path)
    fragment = urllib.parse.unquote(parts.fragment)
    if target.startswith("/"):
        return "an absolute path (the book may be served from any folder)"
    if target == "":
        dest = page_path
    else:
        dest = os.path.normpath(os.path.join(os.path.dirname(page_path), target))
    if dest != book and not dest.startswith(book + os.sep):
        # Outside the book: a file of the repository, named from the page's source.
        counts["repository"] += 1
        page_rel = os.path.relpath(page_path, book)
        source_dir = os.path.dirname(os.path.join(src, page_rel))
        in_repo = os.path.normpath(os.path.join(source_dir, target))
        if not (in_repo == repo or in_repo.startswith(repo + os.sep)):
            return "leaves the repository"
        if not os.path.exists(in_repo):
            return "no such file in the repository (%s)" % os.path.relpath(in_repo, repo)
        return None
    if os.path.isdir(dest):
        dest = os.path.join(dest, "index.html")
    if not os.path.exists(dest):
        return "no such file in the book (%s)" % os.path.relpath(dest, book)
    if fragment and dest.endswith(".html"):
        if fragment not in read_page(dest, cache).ids:
            return "no id '%s' on %s" % (fragment, os.path.relpath(dest, book))
    return None


# Markdown ---------------------------------------------------------------------------

FENCE = re.compile(r"^\s*(```|~~~)")
CODE_SPAN = re.compile(r"(`+)(?:(?!\1).)+?\1")
MD_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HTML_LINK = re.compile(r"<(?:img|a|source)\b[^>]*?\b(?:src|href)\s*=\s*\"([^\"]+)\"", re.I)
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


def heading_id(text):
    """The id GitHub and mdBook give a heading: lower case, markup and punctuation
    dropped, spaces to hyphens."""
    text = re.sub(r"<[^>]+>", "", text)
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = text.replace("`", "").strip().lower()
    text = "".join(c for c in text if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def markdown_lines(path, keep_code_spans=False):
    """(line number, text) of a Markdown file outside code blocks, code spans removed
    unless `keep_code_spans` (headings keep theirs: their text makes the id)."""
    inside = None
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            fence = FENCE.match(line)
            if fence:
                if inside is None:
                    inside = fence.group(1)
                elif fence.group(1) == inside:
                    inside = None
                continue
            if inside is None:
                yield number, line if keep_code_spans else CODE_SPAN.sub("", line)


def markdown_ids(path, cache):
    if path not in cache:
        ids, seen = set(), {}
        for _, line in markdown_lines(path, keep_code_spans=True):
            m = HEADING.match(line)
            if m:
                base = heading_id(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                ids.add(base if n == 0 else "%s-%d" % (base, n))
            for anchor in re.findall(r"<a\s+(?:id|name)=\"([^\"]+)\"", line):
                ids.add(anchor)
        cache[path] = ids
    return cache[path]


def markdown_files(paths):
    """The Markdown files of `paths`: files as given, folders walked in sorted order
    (hidden ones left out)."""
    files = []
    for p in paths:
        if os.path.isdir(p):
            for root, dirs, names in os.walk(p):
                dirs[:] = sorted(d for d in dirs if not d.startswith("."))
                files += [os.path.join(root, n) for n in sorted(names) if n.endswith(".md")]
        else:
            files.append(p)
    return files


def check_markdown(paths):
    files = markdown_files(paths)
    cache, broken, links = {}, [], 0
    for path in files:
        for number, line in markdown_lines(path):
            for url in MD_LINK.findall(line) + HTML_LINK.findall(line):
                links += 1
                why = check_markdown_link(path, url, cache)
                if why:
                    broken.append((path, number, url, why))
    return broken, {"files": len(files), "links": links}


def check_markdown_link(path, url, cache):
    if EXTERNAL.match(url) or url.startswith("//"):
        return None
    parts = urllib.parse.urlsplit(url)
    target = urllib.parse.unquote(parts.path)
    fragment = urllib.parse.unquote(parts.fragment)
    if target.startswith("/"):
        return "an absolute path"
    dest = os.path.normpath(os.path.join(os.path.dirname(path), target)) if target else path
    if not os.path.exists(dest):
        return "no such file (%s)" % dest
    if fragment and dest.endswith(".md") and fragment not in markdown_ids(dest, cache):
        return "no heading '%s' in %s" % (fragment, dest)
    return None


# Pages as generated ------------------------------------------------------------------

# A rustdoc intra-doc link ([`Name`], [`Name::member`]) copied from a doc comment: no
# target, so the page shows the brackets, and a reader has nowhere to go.
RUSTDOC_LINK = re.compile(r"\[`[\w:]+`\](?![(\[])")


def check_structure(paths):
    """What a generated page (docs/reference/) must not hold, as (file, line, text,
    why): a level-1 heading after its title (the book shows it as a chapter of its
    own, `# Safety` from a doc comment), and a rustdoc-style link, in the text or in a
    code block."""
    files = markdown_files(paths)
    found = []
    for path in files:
        titles = 0
        for number, line in markdown_lines(path, keep_code_spans=True):
            m = HEADING.match(line)
            if m and len(m.group(1)) == 1:
                titles += 1
                if titles > 1:
                    found.append((path, number, line.strip(), "a second top-level heading"))
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                for link in RUSTDOC_LINK.findall(line):
                    found.append((path, number, link, "a rustdoc-style link, to nowhere"))
    return found, {"files": len(files)}


def main(argv):
    if len(argv) >= 2 and argv[0] == "html" and len(argv) == 3:
        broken, counts = check_html(argv[1], argv[2])
        summary = "%(pages)d pages, %(links)d links (%(repository)d to repository files)" % counts
    elif len(argv) >= 2 and argv[0] == "markdown":
        broken, counts = check_markdown(argv[1:])
        summary = "%(files)d Markdown files, %(links)d links" % counts
    elif len(argv) >= 2 and argv[0] == "generated":
        broken, counts = check_structure(argv[1:])
        summary = "%(files)d generated pages" % counts
        for path, line, text, why in broken:
            print("%s:%d: %s: %s" % (path, line, text, why))
        if broken:
            print("error: %d problem(s) in %s" % (len(broken), summary), file=sys.stderr)
            return 1
        print("ok: %s, one title each and no rustdoc-style link" % summary)
        return 0
    else:
        sys.stderr.write(__doc__)
        return 2
    for path, line, url, why in broken:
        print("%s:%d: %s: %s" % (path, line, url, why))
    if broken:
        print("error: %d broken link(s) in %s" % (len(broken), summary), file=sys.stderr)
        return 1
    print("ok: %s, all resolve" % summary)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
